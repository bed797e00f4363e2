// The command-line front (core/cli.h: validators, run's exit codes, output checks) and all-or-nothing outputs
// (solvers/base/atomic_file.h).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <fstream>
#include <string>
#include <vector>

#include "solvers/base/atomic_file.h"
#include "core/cli.h"
#include "solvers/base/error.h"

namespace db {
namespace {

namespace fs = std::filesystem;

// The validator's message for `value` ("" when accepted).
std::string check(const CLI::Validator& v, std::string value) { return v(value); }

TEST(CliValidators, IntegerNamesEachKindOfMistake) {
  const CLI::Validator frames = cli::Integer(1, 100000);
  EXPECT_EQ(check(frames, "20"), "");
  EXPECT_EQ(check(frames, "+7"), "");
  EXPECT_EQ(check(frames, "2.5"), "2.5 is not a whole number");
  EXPECT_EQ(check(frames, "1e10"), "1e10 is outside [1, 100000]");
  // Scientific notation is a number too, when it names a whole one; the option converts what it names.
  EXPECT_EQ(check(frames, "1e3"), "");
  EXPECT_EQ(check(frames, "2.50E1"), "");
  EXPECT_EQ(check(frames, "1e+2"), "");
  EXPECT_EQ(check(frames, "1.5e0"), "1.5e0 is not a whole number");
  EXPECT_EQ(check(frames, "1e-1"), "1e-1 is not a whole number");
  EXPECT_EQ(check(frames, "1e"), "1e is not a whole number");
  EXPECT_EQ(check(frames, ".5e1"), ".5e1 is not a whole number");
  EXPECT_EQ(check(frames, "1e999999999"), "1e999999999 is not a whole number");
  std::string value = "2.50e1";
  EXPECT_EQ(frames(value), "");
  EXPECT_EQ(value, "25");
  EXPECT_EQ(check(frames, "nan"), "nan is not a whole number");
  EXPECT_EQ(check(frames, "0x10"), "0x10 is not a whole number");
  EXPECT_EQ(check(frames, ""), " is not a whole number");
  EXPECT_EQ(check(frames, "-1"), "-1 is outside [1, 100000]");
  EXPECT_EQ(check(frames, "100001"), "100001 is outside [1, 100000]");
  EXPECT_EQ(check(frames, "99999999999999999999999"), "99999999999999999999999 is outside [1, 100000]");
}

TEST(CliValidators, RealRejectsNonFiniteAndOutOfRange) {
  const CLI::Validator w = cli::Real(1e-8, 1e8);
  EXPECT_EQ(check(w, "2.5"), "");
  EXPECT_EQ(check(w, "1e3"), "");
  EXPECT_EQ(check(w, "nan"), "nan is not a finite number");
  EXPECT_EQ(check(w, "inf"), "inf is not a finite number");
  EXPECT_EQ(check(w, "1e999"), "1e999 is not a finite number");
  EXPECT_EQ(check(w, "abc"), "abc is not a number");
  EXPECT_EQ(check(w, "0x1p3"), "0x1p3 is not a number");
  EXPECT_EQ(check(w, "2,5"), "2,5 is not a number");
  EXPECT_EQ(check(w, "0"), "0 is outside [1e-08, 1e+08]");
  EXPECT_EQ(check(w, "-1"), "-1 is outside [1e-08, 1e+08]");
}

TEST(CliValidators, OneOfListsTheChoices) {
  const CLI::Validator m = cli::OneOf({"lap", "tf", "lri"});
  EXPECT_EQ(check(m, "tf"), "");
  EXPECT_EQ(check(m, "TF"), "'TF' is not one of: lap, tf, lri");
}

// Runs `app` on `args` through cli::run; returns the exit code, the stderr text in `err`.
int run_app(CLI::App& app, std::vector<std::string> args, const std::function<int()>& body, std::string& err) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  testing::internal::CaptureStderr();
  const int code = cli::run(app, static_cast<int>(argv.size()), argv.data(), body);
  err = testing::internal::GetCapturedStderr();
  return code;
}

TEST(CliRun, ParseErrorsExitOneNamingTheOption) {
  std::string err;
  long long frames = 1;
  auto make = [&](CLI::App& app) { app.add_option("--frames", frames)->transform(cli::Integer(1, 100000)); };
  int ran = 0;
  {
    CLI::App app("t", "tool");
    make(app);
    EXPECT_EQ(run_app(app, {"tool", "--frame", "20"}, [&] { return ++ran; }, err), 1);
    EXPECT_NE(err.find("unknown option --frame (did you mean --frames?)"), std::string::npos) << err;
  }
  {
    CLI::App app("t", "tool");
    make(app);
    EXPECT_EQ(run_app(app, {"tool", "--frames", "1e10"}, [&] { return ++ran; }, err), 1);
    EXPECT_NE(err.find("--frames: 1e10 is outside [1, 100000]"), std::string::npos) << err;
  }
  EXPECT_EQ(ran, 0) << "the body must not run after a parse error";
}

TEST(CliRun, ExceptionsMapToTheExitCodePolicy) {
  auto code_of = [](const std::function<int()>& body) {
    CLI::App app("t", "tool");
    std::string err;
    return run_app(app, {"tool"}, body, err);
  };
  EXPECT_EQ(code_of([] { return 0; }), 0);
  EXPECT_EQ(code_of([]() -> int { throw UsageError("x"); }), 1);
  EXPECT_EQ(code_of([]() -> int { throw Error("x"); }), 1);
  EXPECT_EQ(code_of([]() -> int { throw InputError("x"); }), 2);
  EXPECT_EQ(code_of([]() -> int { throw SolverError("x"); }), 3);
  EXPECT_EQ(code_of([]() -> int { throw BudgetError("x"); }), 4);
  EXPECT_EQ(code_of([]() -> int { throw std::bad_alloc(); }), 4);
}

TEST(CliRun, UnknownSubcommandIsNamed) {
  CLI::App app("t", "tool");
  app.require_subcommand(1);
  app.add_subcommand("deform", "");
  app.add_subcommand("solvers", "");
  std::string err;
  EXPECT_EQ(run_app(app, {"tool", "deforn"}, [] { return 0; }, err), 1);
  EXPECT_NE(err.find("unknown command 'deforn' (commands: deform, solvers)"), std::string::npos) << err;
}

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cli_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void touch(const std::string& name, const std::string& text = "x") const { std::ofstream(path(name)) << text; }
  std::vector<std::string> listing() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  fs::path dir_;
};

// The UsageError message of check_output ("" when it passes).
std::string output_error(const std::string& path, const std::vector<std::string>& ext,
                         const std::vector<std::string>& inputs = {}) {
  try {
    cli::check_output("--out", path, ext, inputs);
  } catch (const UsageError& e) {
    return e.what();
  }
  return {};
}

using CheckOutput = TempDir;

TEST_F(CheckOutput, AcceptsAWritablePathWithASupportedExtension) {
  EXPECT_EQ(output_error(path("a.ply"), {".off", ".ply"}), "");
  EXPECT_EQ(output_error(path("A.PLY"), {".off", ".ply"}), "") << "extensions compare case-insensitively";
  EXPECT_EQ(output_error(path("a.anything"), {}), "");
}

TEST_F(CheckOutput, RefusesEachBadPathWithItsCause) {
  EXPECT_NE(output_error("", {}).find("empty path"), std::string::npos);
  EXPECT_NE(output_error(path("a.stl"), {".off", ".ply"}).find("unsupported extension '.stl'"), std::string::npos);
  EXPECT_NE(output_error(path("no/such/a.ply"), {".ply"}).find("does not exist"), std::string::npos);
  touch("file");
  EXPECT_NE(output_error(path("file/a.ply"), {".ply"}).find("'" + path("file") + "' is not a directory"),
            std::string::npos);
  fs::create_directory(path("d.ply"));
  EXPECT_NE(output_error(path("d.ply"), {".ply"}).find("is a directory"), std::string::npos);
  if (::geteuid() != 0) {  // root writes anywhere
    fs::create_directory(path("ro"));
    fs::permissions(path("ro"), fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_NE(output_error(path("ro/a.ply"), {".ply"}).find("not writable"), std::string::npos);
    fs::permissions(path("ro"), fs::perms::owner_all);
  }
}

TEST_F(CheckOutput, RefusesAnInputHoweverSpelled) {
  touch("mesh.off");
  const std::string in = path("mesh.off");
  const std::string respelled = (dir_ / "." / ".." / dir_.filename() / "mesh.off").string();
  EXPECT_NE(output_error(respelled, {".off"}, {in}).find("is an input file"), std::string::npos);
  fs::create_symlink(in, path("link.off"));
  EXPECT_NE(output_error(path("link.off"), {".off"}, {in}).find("is an input file"), std::string::npos);
  // An input that does not exist yet is compared by its spelling.
  EXPECT_NE(output_error(path("new.off"), {".off"}, {path("./new.off")}).find("is an input file"), std::string::npos);
  EXPECT_EQ(output_error(path("other.off"), {".off"}, {in}), "");
}

TEST_F(CheckOutput, DirectoryMustExist) {
  EXPECT_NO_THROW(cli::check_directory("--factor-dir", dir_.string()));
  EXPECT_THROW(cli::check_directory("--factor-dir", path("missing")), UsageError);
  touch("f");
  EXPECT_THROW(cli::check_directory("--factor-dir", path("f")), UsageError);
}

using Staged = TempDir;

TEST_F(Staged, CommitRenamesEveryOutputTogether) {
  StagedOutputs out;
  const std::string mesh = out.stage(path("r.ply")), csv = out.stage(path("r.csv"));
  EXPECT_EQ(fs::path(mesh).extension(), ".ply") << "writers choose the format by the extension";
  EXPECT_EQ(fs::path(mesh).parent_path(), dir_) << "renamed within the target's directory";
  std::ofstream(mesh) << "mesh";
  std::ofstream(csv) << "csv";
  EXPECT_EQ(listing().size(), 2u);
  out.commit();
  EXPECT_EQ(listing(), (std::vector<std::string>{"r.csv", "r.ply"}));
}

// Two outputs of one run cannot be one file, however spelled: the second would replace the first, and the kept
// copy of the earlier file with it (an audit found export-system's --out K.mtx --rhs ./K.mtx lose the earlier file).
TEST_F(Staged, TwoOutputsCannotShareAFile) {
  std::ofstream(path("k.mtx")) << "earlier";
  {
    StagedOutputs out;
    std::ofstream(out.stage(path("k.mtx"))) << "matrix";
    EXPECT_THROW(out.stage((fs::path(dir_) / "." / "k.mtx").string()), Error);
    EXPECT_THROW(out.stage(path("k.mtx")), Error);
  }
  std::ifstream in(path("k.mtx"));
  const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept, "earlier");
  EXPECT_EQ(listing(), (std::vector<std::string>{"k.mtx"})) << "no temporary left";
}

TEST_F(Staged, AFailedRunLeavesNothing) {
  {
    StagedOutputs out;
    std::ofstream(out.stage(path("r.ply"))) << "mesh";
    out.stage(path("r.csv"));  // the run failed before writing it
  }
  EXPECT_TRUE(listing().empty());
}

TEST_F(Staged, AFailedRenameTakesBackTheEarlierOutputs) {
  fs::create_directory(path("sub"));
  {
    StagedOutputs out;
    std::ofstream(out.stage(path("r.ply"))) << "mesh";
    std::ofstream(out.stage(path("sub/r.csv"))) << "csv";
    fs::create_directories(path("sub/r.csv/occupied"));  // a non-empty directory where the CSV should go
    EXPECT_THROW(out.commit(), Error);
    EXPECT_FALSE(fs::exists(path("r.ply"))) << "the output renamed before the failure is removed again";
  }
  fs::remove_all(path("sub/r.csv"));
  EXPECT_EQ(listing(), (std::vector<std::string>{"sub"}));
  EXPECT_TRUE(fs::is_empty(path("sub"))) << "the destructor removes the temporary that was not renamed";
}

// The case: the mesh of an earlier run is replaced, then the CSV cannot be: the earlier mesh is left as it
// was (before, the new mesh was removed again and neither the earlier nor the new mesh was left).
TEST_F(Staged, AFailedCommitLeavesTheEarlierOutputsAsTheyWere) {
  std::ofstream(path("r.ply")) << "earlier mesh";
  fs::create_directory(path("sub"));
  {
    StagedOutputs out;
    std::ofstream(out.stage(path("r.ply"))) << "new mesh";
    std::ofstream(out.stage(path("sub/r.csv"))) << "new csv";
    fs::create_directories(path("sub/r.csv/occupied"));  // a non-empty directory where the CSV should go
    EXPECT_THROW(out.commit(), Error);
  }
  std::ifstream in(path("r.ply"));
  const std::string mesh((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(mesh, "earlier mesh") << "the earlier output is put back";
  fs::remove_all(path("sub/r.csv"));
  EXPECT_EQ(listing(), (std::vector<std::string>{"r.ply", "sub"})) << "no temporary and no kept copy is left";
  EXPECT_TRUE(fs::is_empty(path("sub")));
}

TEST_F(Staged, ACommitReplacesTheEarlierOutputsAndKeepsNoCopy) {
  std::ofstream(path("r.ply")) << "earlier mesh";
  StagedOutputs out;
  std::ofstream(out.stage(path("r.ply"))) << "new mesh";
  out.commit();
  std::ifstream in(path("r.ply"));
  const std::string mesh((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(mesh, "new mesh");
  EXPECT_EQ(listing(), (std::vector<std::string>{"r.ply"}));
}

}  // namespace
}  // namespace db
