#include "core/provenance.h"

#include <dlfcn.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "deformbench_build_sha.h"  // DEFORMBENCH_BUILD_SHA, written at every build (cmake/build_sha.cmake)
#include "solvers/base/resources.h"

namespace db {
namespace {

std::string run_command(const std::string& cmd) {
  std::array<char, 256> buf{};
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd.c_str(), "r"), ::pclose);
  if (!pipe) return out;
  while (std::fgets(buf.data(), buf.size(), pipe.get())) out += buf.data();
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string source_dir() {
  if (const char* s = std::getenv("DEFORMBENCH_SOURCE_DIR")) return s;
#ifdef DEFORMBENCH_SOURCE_DIR
  return DEFORMBENCH_SOURCE_DIR;
#else
  return ".";
#endif
}

std::string git_sha() {
  if (const char* s = std::getenv("DEFORMBENCH_GIT_SHA")) return s;  // set by ./run once per job
  // The commit this binary was compiled from (cmake/build_sha.cmake), else the tree's at run time.
  if (const std::string built = DEFORMBENCH_BUILD_SHA; built != "unknown") return built;
  const std::string dir = source_dir();
  std::string sha = run_command("git -C '" + dir + "' rev-parse --short=12 HEAD 2>/dev/null");
  if (sha.empty()) return "unknown";
  if (!run_command("git -C '" + dir + "' status --porcelain --untracked-files=no 2>/dev/null").empty())
    sha += "+dirty";
  return sha;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      auto p = line.find(':');
      if (p != std::string::npos) return line.substr(p + 2);
    }
  }
  return "unknown";
}

// OpenBLAS entry points are looked up at run time so the build links against any BLAS the alternatives
// system provides; a reference BLAS simply reports "n/a".
void blas_info(Provenance& p) {
  p.blas = "unknown";
  p.blas_core = "n/a";
  p.blas_threads = 1;
  using CharFn = char* (*)();
  using IntFn = int (*)();
  void* self = ::dlopen(nullptr, RTLD_NOW);
  if (!self) return;
  auto config = reinterpret_cast<CharFn>(::dlsym(self, "openblas_get_config"));
  auto core = reinterpret_cast<CharFn>(::dlsym(self, "openblas_get_corename"));
  auto threads = reinterpret_cast<IntFn>(::dlsym(self, "openblas_get_num_threads"));
  if (config) {
    std::string c = config();
    p.blas = "openblas";
    auto v = c.find("OpenBLAS ");
    if (v != std::string::npos) p.blas = "openblas " + c.substr(v + 9, c.find(' ', v + 9) - (v + 9));
  } else if (::dlsym(self, "dgemm_")) {
    p.blas = "reference-or-other";
  }
  if (core) p.blas_core = core();
  if (threads) p.blas_threads = threads();
}

std::string utc_now() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> Provenance::columns() const {
  return {{"git_sha", git_sha},
          {"blas", blas},
          {"blas_core", blas_core},
          {"blas_coretype_env", blas_coretype_env.empty() ? "auto" : blas_coretype_env},
          {"blas_threads", std::to_string(blas_threads)},
          {"build_threads", std::to_string(build_threads)},
          {"hardware_threads", std::to_string(hardware_threads)},
          {"cpu", cpu},
          {"compiler", compiler},
          {"timestamp", timestamp}};
}

const Provenance& provenance() {
  static const Provenance p = [] {
    Provenance q;
    q.git_sha = git_sha();
    blas_info(q);
    if (const char* e = std::getenv("OPENBLAS_CORETYPE")) q.blas_coretype_env = e;
    q.build_threads = worker_threads();
    q.hardware_threads = static_cast<int>(std::thread::hardware_concurrency());
    q.cpu = cpu_model();
#if defined(__clang__)
    q.compiler = fmt::format("clang {}.{}", __clang_major__, __clang_minor__);
#elif defined(__GNUC__)
    q.compiler = fmt::format("gcc {}.{}", __GNUC__, __GNUC_MINOR__);
#else
    q.compiler = "unknown";
#endif
    q.timestamp = utc_now();
    return q;
  }();
  return p;
}

std::string provenance_summary() {
  const auto& p = provenance();
  return fmt::format("git {} | {} core {} ({}) | {} BLAS threads, {} build threads, {} hw threads", p.git_sha,
                     p.blas, p.blas_core,
                     p.blas_coretype_env.empty() ? "auto-detected" : "OPENBLAS_CORETYPE=" + p.blas_coretype_env,
                     p.blas_threads, p.build_threads, p.hardware_threads);
}

}  // namespace db
