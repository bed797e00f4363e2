// Fuzzing the readers (issue 13, item 8): small OFF, PLY (ASCII, binary, triangle strips), OBJ and STL (ASCII,
// binary with a header that begins with "solid") files written here, the bundled Botsch-Sorkine cylinder
// (.off/.sel/.def), the .edit files of data/edits, an edit's targets file (issue 28) and a driver's TOML options file
// (issue 28: read as every driver reads one) are mutated with a fixed seed (byte flips, truncations, count changes,
// swapped numbers, lines dropped or repeated, junk inserted) and loaded in process. Each case must load or throw
// db::InputError (exit 2; an options file: CLI::ParseError, exit 1): no other exception, no crash, no hang, no NaN
// coordinate, target or option value, no index out of range.
//
// Environment: DEFORMBENCH_FUZZ_CASES (default 3000), DEFORMBENCH_FUZZ_CASE=i runs case i alone (each case draws
// from its own generator seeded with its number, so a failure replays alone), DEFORMBENCH_FUZZ_VERBOSE=1 prints
// every case and its outcome, DEFORMBENCH_FUZZ_KEEP=1 keeps the directory of inputs (with DEFORMBENCH_FUZZ_CASE,
// that case's mutated file stays in it). A case still running after kCaseLimit seconds ends the process with the
// case named.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <typeinfo>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "solvers/base/error.h"
#include "core/cli.h"
#include "edit/edit_io.h"
#include "harness/driver.h"
#include "mesh/mesh.h"
#include "mesh/mesh_io.h"
#include "mesh/procedural.h"

namespace db {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kCaseLimit = 20.0;  // seconds; generous for sanitizer builds: a case takes milliseconds

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void spit(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary | std::ios::trunc) << s; }

// ---------------------------------------------------------------- base inputs
std::string octahedron_off() {
  return "OFF # an octahedron\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n3 0 2 4\n3 2 1 4\n3 1 3 4\n"
         "3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
}

std::string coloured_off() {
  return "COFF\n4 2 5\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 255\n"
         "4 0 1 2 3 1 1 1\n3 0 2 3\n";
}

std::string ascii_ply() {
  return "ply\nformat ascii 1.0\ncomment strips and an extra element\nelement vertex 5\nproperty float x\n"
         "property float y\nproperty double z\nproperty uchar red\nelement face 1\n"
         "property list uchar int vertex_indices\nelement tristrips 1\nproperty list int int vertex_indices\n"
         "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n"
         "0 1 0 4\n0.5 0.5 1 5\n3 0 1 4\n7 1 2 4 -1 2 3 4\n0 1\n1 2\n";
}

template <class T>
void put(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof(v));
}

std::string binary_ply() {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar flags\nelement face 2\nproperty list uchar uint vertex_indices\n"
      "element material 1\nproperty list ushort double values\nend_header\n";
  const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5f}};
  for (const auto& p : xyz) {
    for (float c : p) put(s, c);
    put<std::uint8_t>(s, 7);
  }
  put<std::uint8_t>(s, 3);
  for (std::uint32_t i : {0u, 1u, 2u}) put(s, i);
  put<std::uint8_t>(s, 4);
  for (std::uint32_t i : {0u, 2u, 3u, 1u}) put(s, i);
  put<std::uint16_t>(s, 2);
  put(s, 0.5);
  put(s, -2.0);
  return s;
}

std::string quad_obj() {
  return "# quads\nmtllib x.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0 0.2 0.3 0.4\nv 0 1 0\nv 0.5 0.5 1.0 1.0\nvt 0 0\n"
         "vn 0 0 1\ng g1\ns 1\nusemtl m\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -5//1 -4//1 -1//1\nf 2 3 5\n";
}

// Two solids, keywords in mixed case, the same corner spelled "1" and "1.0" (one vertex once welded).
std::string ascii_stl() {
  auto facet = [](const char* a, const char* b, const char* c) {
    return std::string("  facet normal 0 0 1\n    outer loop\n      vertex ") + a + "\n      vertex " + b +
           "\n      vertex " + c + "\n    endloop\n  endfacet\n";
  };
  return "solid first\n" + facet("0 0 0", "1 0 0", "0 1 0") + facet("1.0 0 0", "1 1 0", "0 1 0") +
         "endsolid first\nSOLID second\n" + facet("0 0 0", "0 1 0", "0.5 0.5 1e0") + "ENDSOLID\n";
}

// Binary, its header beginning with "solid" as many exporters write it: the size decides that it is binary.
std::string binary_stl() {
  std::string s = "solid exported by a CAD tool";
  s.resize(80, ' ');
  const float tris[3][9] = {
      {0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 0, 0, 0, 1, 0, 0.5f, 0.5f, 1}};
  put<std::uint32_t>(s, 3);
  for (const auto& t : tris) {
    for (float n : {0.f, 0.f, 1.f}) put(s, n);
    for (float c : t) put(s, c);
    put<std::uint16_t>(s, 0);
  }
  return s;
}

// ---------------------------------------------------------------- mutations
const char* const kNumbers[] = {"0",  "-1", "1", "2", "3", "255", "256", "65536", "2147483647", "2147483648",
                                "4294967295", "4294967296", "1000000000000", "9223372036854775807",
                                "99999999999999999999", "-2147483648", "nan", "inf", "-inf", "1e308", "1e-320",
                                "-0", "0x10", "1e400", "3.5", ""};
const char* const kJunk[] = {"\n", "\r\n", "#", " ", "\t", "-", "/", "//", ",", "=", ":", "\0", "\xff", "e",
                             "end_header\n", "element x 1000000000000\n", "property list uint int vertex_indices\n",
                             "format binary_little_endian 1.0\n", "f 1 2 3\n", "v 1 2 3\n", "3 0 1 2\n",
                             "mesh = ../meshes/dino.off\n", "roi = all\n", "handle = nearest:0,0,0,5\n",
                             "transform = matrix:1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1\n", "kring:0,1000000\n",
                             "indices:../edits/dino_head.edit\n", "box:1,1,1,0,0,0", "sphere:0,0,0,-1",
                             "[", "]", "\"", "'", "[table]\n", "[[list]]\n", "tier = [\"a=x.off\",\n", "frames = \n",
                             "frames = 1\n", "x = {a = 1}\n", "\"\"\"", "1979-05-27\n"};

struct NumberToken {
  std::size_t pos, len;
};

std::vector<NumberToken> numbers_in(const std::string& s) {
  std::vector<NumberToken> out;
  for (std::size_t i = 0; i < s.size();) {
    const bool start = std::isdigit(static_cast<unsigned char>(s[i])) || (s[i] == '-' && i + 1 < s.size() &&
                                                                          std::isdigit(static_cast<unsigned char>(s[i + 1])));
    if (!start) {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' || s[j] == 'e')) ++j;
    out.push_back({i, j - i});
    i = j;
  }
  return out;
}

std::vector<std::size_t> line_starts(const std::string& s) {
  std::vector<std::size_t> out{0};
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i] == '\n' && i + 1 < s.size()) out.push_back(i + 1);
  return out;
}

// One random mutation of s; `what` gets a short description. Numbers are what a reader trusts (counts, indices,
// coordinates), so most mutations change or swap them.
void mutate(std::string& s, std::mt19937& rng, std::string& what) {
  auto pick = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  // 0 flip, 1 random byte, 2 truncation, 3 number replaced, 4 numbers swapped, 5 line dropped or repeated, 6 junk
  static const int kinds[] = {0, 1, 2, 3, 3, 3, 3, 4, 4, 5, 6, 6};
  const int kind = kinds[pick(std::size(kinds))];
  if (s.empty() || kind == 6) {
    const std::string junk = kJunk[pick(std::size(kJunk))];
    // Whole lines go in at the start of a line, so they stay statements of the format.
    const auto starts = line_starts(s);
    const std::size_t at = s.empty() ? 0 : junk.size() > 1 && junk.back() == '\n' ? starts[pick(starts.size())]
                                                                                     : pick(s.size() + 1);
    s.insert(at, junk.empty() ? std::string(1, '\0') : junk);
    what += " junk@" + std::to_string(at);
    return;
  }
  const auto nums = numbers_in(s);
  const auto lines = line_starts(s);
  switch (kind) {
    case 0: {  // byte flip
      const std::size_t at = pick(s.size());
      s[at] = static_cast<char>(s[at] ^ (1 << pick(8)));
      what += " flip@" + std::to_string(at);
      break;
    }
    case 1: {  // random byte
      const std::size_t at = pick(s.size());
      s[at] = static_cast<char>(pick(256));
      what += " byte@" + std::to_string(at);
      break;
    }
    case 2: {  // truncation
      const std::size_t at = pick(s.size());
      s.resize(at);
      what += " cut@" + std::to_string(at);
      break;
    }
    case 3: {  // count change: a number replaced by an awkward one
      if (nums.empty()) return mutate(s, rng, what);
      const NumberToken t = nums[pick(nums.size())];
      const std::string n = kNumbers[pick(std::size(kNumbers))];
      s.replace(t.pos, t.len, n);
      what += " number@" + std::to_string(t.pos) + "=" + n;
      break;
    }
    case 4: {  // two numbers swapped
      if (nums.size() < 2) return mutate(s, rng, what);
      NumberToken a = nums[pick(nums.size())], b = nums[pick(nums.size())];
      if (a.pos > b.pos) std::swap(a, b);
      if (a.pos == b.pos) return;
      const std::string ta = s.substr(a.pos, a.len), tb = s.substr(b.pos, b.len);
      s.replace(b.pos, b.len, ta);
      s.replace(a.pos, a.len, tb);
      what += " swap@" + std::to_string(a.pos) + "," + std::to_string(b.pos);
      break;
    }
    default: {  // a line dropped or repeated
      const std::size_t l = pick(lines.size());
      const std::size_t b = lines[l], e = l + 1 < lines.size() ? lines[l + 1] : s.size();
      const std::string text = s.substr(b, e - b);
      if (pick(2) == 0) {
        s.erase(b, e - b);
        what += " drop-line" + std::to_string(l);
      } else {
        s.insert(b, text);
        what += " repeat-line" + std::to_string(l);
      }
    }
  }
}

// ---------------------------------------------------------------- targets
// A load's refusal of bad input: InputError (exit 2), or for an options file CLI11's ParseError, which cli::run
// turns into exit 1 (docs/cli.md, exit codes).
struct Target {
  std::string name;
  fs::path file;                    // rewritten every case
  std::string base;                 // its unmutated content
  std::function<void()> load;       // loads and checks what loaded; throws InputError for bad input
};

void check_mesh(const Mesh& m, const std::string& what) {
  if (!m.V.allFinite()) throw std::logic_error(what + ": a non-finite coordinate was loaded");
  if (m.F.size() > 0 && (m.F.minCoeff() < 0 || m.F.maxCoeff() >= m.num_vertices()))
    throw std::logic_error(what + ": a face index out of range was loaded");
}

void check_case(const EditCase& c, const std::string& what) {
  check_mesh(c.mesh, what);
  if (static_cast<int>(c.edit.roles.size()) != c.mesh.num_vertices())
    throw std::logic_error(what + ": the edit's roles do not match the mesh");
  if (!c.edit.transform.allFinite()) throw std::logic_error(what + ": a non-finite transform was loaded");
}

// A driver's options file, read as every driver reads one (harness::add_config_option: strict TOML); what it sets
// must satisfy the options' validators (no NaN, no value out of range).
void load_config(const fs::path& file) {
  CLI::App app("fuzzed driver", "exp_fuzzed");
  long long frames = 20, repeats = 1;
  double tolerance = 0.5;
  std::vector<std::string> tier;
  std::string results;
  bool dry_run = false;
  app.add_option("--frames", frames)->check(cli::Integer(1, 100000));
  app.add_option("--repeats", repeats)->check(cli::Integer(1, 1000));
  app.add_option("--tolerance", tolerance)->check(cli::Real(0, 1));
  app.add_option("--tier", tier);
  app.add_option("--results", results);
  app.add_flag("--dry-run", dry_run);
  harness::add_config_option(app, "");
  app.parse(std::vector<std::string>{file.string(), "--config"});  // CLI11 takes the arguments reversed
  if (!(tolerance >= 0 && tolerance <= 1) || frames < 1 || frames > 100000 || repeats < 1 || repeats > 1000)
    throw std::logic_error(file.string() + ": a value outside its option's range was accepted");
}

std::string config_toml() {
  return "# a driver's options\nframes = 20\nrepeats = 3\ntolerance = 0.25\n"
         "tier = [\"a=x.off\", \"b=y.off\"]  # NAME=MESH\nresults = \"results\"\ndry-run = true\n";
}

// A tube written as OFF, with a .sel of its bottom (fixed) and top (handle) rings.
Mesh small_tube() { return make_cylinder(12, 16, 1.0, 4.0); }

std::string tube_sel(const Mesh& m) {
  std::string s = "# 0 fixed, 1 free, 2 handle\n";
  for (int v = 0; v < m.num_vertices(); ++v) s += m.V(v, 2) < 0.5 ? "0\n" : m.V(v, 2) > 3.5 ? "2\n" : "1\n";
  return s;
}

class Fuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("deformbench_fuzz_" + std::to_string(::getpid()));
    for (const char* sub : {"m", "bs08", "edits", "meshes", "generated"}) fs::create_directories(dir_ / sub);
    const fs::path src = DEFORMBENCH_SOURCE_DIR;
    mesh_target("octa.off", octahedron_off());
    mesh_target("coloured.off", coloured_off());
    mesh_target("strips.ply", ascii_ply());
    mesh_target("binary.ply", binary_ply());
    mesh_target("quad.obj", quad_obj());
    mesh_target("text.stl", ascii_stl());
    mesh_target("binary.stl", binary_stl());
    write_mesh((dir_ / "m" / "tube.off").string(), make_cylinder(5, 6, 1.0, 2.0));
    mesh_target("tube.off", slurp(dir_ / "m" / "tube.off"));
    // The bundled BS08 cylinder: its .sel, .def and .off in turn, loaded as a stem.
    for (const char* ext : {".sel", ".def", ".off"}) fs::copy_file(src / "data/bs08" / ("cylinder" + std::string(ext)),
                                                                 dir_ / "bs08" / ("cylinder" + std::string(ext)));
    const std::string stem = (dir_ / "bs08" / "cylinder").string();
    for (const char* ext : {".sel", ".def", ".off"}) {
      const fs::path f = stem + ext;
      targets_.push_back({f.filename().string(), f, slurp(f), [stem] { check_case(load_edit_case(stem), stem); }});
    }
    // The .edit files of data/edits, their meshes replaced by a small tube (same names, so they load).
    const Mesh tube = small_tube();
    for (const char* name : {"meshes/armadillo.off", "meshes/dino.off", "meshes/cactus.off"})
      write_mesh((dir_ / name).string(), tube);
    for (const auto& e : fs::directory_iterator(src / "data" / "edits"))  // the generated tiers' meshes
      if (e.path().extension() == ".edit" && e.path().stem().string().rfind("armadillo_loop", 0) == 0) {
        const std::string level = e.path().stem().string().substr(0, e.path().stem().string().find('_', 10));
        write_mesh((dir_ / "generated" / (level + ".off")).string(), tube);
      }
    spit(dir_ / "meshes" / "cactus_cgal.sel", tube_sel(tube));
    fs::copy_file(src / "data/bs08/cylinder.def", dir_ / "meshes" / "cactus_cgal.def");
    fs::copy_file(src / "data/bs08/bar.off", dir_ / "bs08" / "bar.off");  // bar_bend.edit selects by boxes on it
    for (const auto& e : fs::directory_iterator(src / "data" / "edits")) {
      if (e.path().extension() != ".edit") continue;
      const fs::path f = dir_ / "edits" / e.path().filename();
      fs::copy_file(e.path(), f);
      targets_.push_back({f.filename().string(), f, slurp(f), [f] { check_case(load_edit_case(f.string()), f); }});
    }
    targets_file_target(tube);
    const fs::path config = dir_ / "driver.toml";
    spit(config, config_toml());
    targets_.push_back({"driver.toml", config, config_toml(), [config] { load_config(config); }});
  }

  // A per-vertex drag of the tube's top ring (3 frames up its axis): its targets file is what is mutated.
  void targets_file_target(const Mesh& tube) {
    const fs::path edit = dir_ / "m" / "drag.edit", targets = dir_ / "m" / "drag.targets";
    write_mesh((dir_ / "m" / "drag.off").string(), tube);
    spit(edit, "mesh = drag.off\nroi = all\nhandle = box:-9,-9,3.5,9,9,9\ntargets = drag.targets\n");
    std::string lines = "# x y z per handle vertex, frame after frame\n";
    for (int frame = 1; frame <= 3; ++frame)
      for (int v = 0; v < tube.num_vertices(); ++v)
        if (tube.V(v, 2) > 3.5) lines += fmt::format("{} {} {}\n", tube.V(v, 0), tube.V(v, 1), tube.V(v, 2) + 0.1 * frame);
    targets_.push_back({"drag.targets", targets, lines, [edit] {
                          const EditCase c = load_edit_case(edit.string());
                          check_case(c, edit.string());
                          if (!c.edit.targets.allFinite()) throw std::logic_error("a non-finite target was loaded");
                        }});
    spit(targets, lines);
  }
  void TearDown() override {
    if (std::getenv("DEFORMBENCH_FUZZ_KEEP")) std::cerr << "fuzz inputs kept in " << dir_ << "\n";
    else fs::remove_all(dir_);
  }

  void mesh_target(const std::string& name, const std::string& content) {
    const fs::path f = dir_ / "m" / name;
    spit(f, content);
    targets_.push_back({name, f, content, [f] {
                          const Mesh m = read_mesh(f.string());
                          check_mesh(m, f.string());
                          try {
                            validate_mesh(m, Manifold::Allowed);
                          } catch (const InputError&) {
                          }
                        }});
  }

  fs::path dir_;
  std::vector<Target> targets_;
};

// Watchdog and crash reporter: what the case running now is, for the message.
char g_case[512] = "";
std::atomic<long long> g_case_start_ns{-1};

void say_case_and_die(int sig) {
  const char head[] = "\nfuzz_test: died in ";
  (void)!::write(2, head, sizeof(head) - 1);
  (void)!::write(2, g_case, std::strlen(g_case));
  (void)!::write(2, "\n", 1);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

long long now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

class Watchdog {
 public:
  Watchdog()
      : thread_([this] {
          while (!stop_) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            const long long start = g_case_start_ns;
            if (start >= 0 && (now_ns() - start) * 1e-9 > kCaseLimit) {
              std::fprintf(stderr, "fuzz_test: case still running after %.0f s (a hang): %s\n", kCaseLimit, g_case);
              std::_Exit(3);
            }
          }
        }) {}
  ~Watchdog() {
    stop_ = true;
    thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

long env_long(const char* name, long fallback) {
  const char* v = std::getenv(name);
  return v ? std::strtol(v, nullptr, 10) : fallback;
}

TEST_F(Fuzz, EveryBaseInputLoads) {
  for (const Target& t : targets_) EXPECT_NO_THROW(t.load()) << t.name;
}

TEST_F(Fuzz, MutatedInputsLoadOrRaiseInputError) {
  const long cases = env_long("DEFORMBENCH_FUZZ_CASES", 3000), only = env_long("DEFORMBENCH_FUZZ_CASE", -1);
  const bool verbose = env_long("DEFORMBENCH_FUZZ_VERBOSE", 0) != 0;
  for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL}) std::signal(sig, say_case_and_die);
  Watchdog watchdog;
  long loaded = 0, refused = 0, failures = 0;
  double slowest = 0;
  const auto t0 = Clock::now();
  for (long i = only >= 0 ? only : 0; i < (only >= 0 ? only + 1 : cases) && failures < 10; ++i) {
    std::mt19937 rng(static_cast<std::mt19937::result_type>(20240 + i));
    const Target& t = targets_[static_cast<std::size_t>(i) % targets_.size()];
    std::string input = t.base, what;
    static const int stacked[] = {1, 1, 1, 1, 1, 2, 2, 2, 3, 3};  // mostly one mutation, so it reaches the reader
    const int n = stacked[std::uniform_int_distribution<std::size_t>(0, std::size(stacked) - 1)(rng)];
    for (int k = 0; k < n; ++k) mutate(input, rng, what);
    std::snprintf(g_case, sizeof(g_case), "case %ld (DEFORMBENCH_FUZZ_CASE=%ld): %s:%s", i, i, t.name.c_str(),
                  what.c_str());
    spit(t.file, input);
    const long long start = now_ns();
    g_case_start_ns = start;
    try {
      t.load();
      ++loaded;
      if (verbose) std::cout << g_case << ": loaded\n";
    } catch (const InputError& e) {
      ++refused;
      if (verbose) std::cout << g_case << ": " << e.what() << "\n";
    } catch (const CLI::ParseError& e) {  // an options file's refusal (exit 1)
      ++refused;
      if (verbose) std::cout << g_case << ": " << e.what() << "\n";
    } catch (const std::exception& e) {
      ++failures;
      ADD_FAILURE() << g_case << ": " << typeid(e).name() << ": " << e.what();
    }
    g_case_start_ns = -1;
    slowest = std::max(slowest, (now_ns() - start) * 1e-9);
    if (only < 0) spit(t.file, t.base);
  }
  std::signal(SIGABRT, SIG_DFL);
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  std::cout << fmt::format("{} cases in {:.1f} s (slowest {:.3f} s): {} loaded, {} refused with InputError\n",
                           loaded + refused + failures, seconds, slowest, loaded, refused);
  if (only < 0) {
    // Both outcomes occur, or the mutations are not reaching the readers.
    EXPECT_GT(loaded, cases / 20);
    EXPECT_GT(refused, cases / 4);
  }
}

}  // namespace
}  // namespace db
