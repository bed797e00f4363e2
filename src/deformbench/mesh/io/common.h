#pragma once
//! What every mesh reader and writer shares: reading a file whole (with the first-line guard), failing with the
//! file and line named, a line cursor and tokenizer, exact number parsing, the checks on declared counts and
//! coordinates, building the Mesh, and the buffered text output that writes doubles exactly.
#include <cstddef>
#include <cstring>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "mesh/mesh.h"

namespace db {
class InputFile;
}

namespace db::io {

//! Every file read with read_file starts with a short text line (OFF, PLY's "ply", ASCII STL's "solid", an OBJ
//! statement or comment): a file whose first kMaxFirstLine bytes hold no line end is not a mesh file.
constexpr std::size_t kMaxFirstLine = 64 << 10;

//! The whole file, read only once its first line has ended within kMaxFirstLine bytes: a large file that is no
//! mesh (a sparse file of zeros) is refused after those bytes, not after reading it all.
//! \throw InputError unreadable file, or no line end in the first kMaxFirstLine bytes.
std::string read_file(const std::string& path);
//! The same, for a file already open of which `head` has been read.
std::string read_file(InputFile& in, const std::string& path, std::string head);

//! \throw InputError "PATH: line LINE: MSG".
[[noreturn]] void fail(const std::string& path, int line, const std::string& msg);

//! Line cursor over a text buffer; strips '\r' and, when asked, '#' comments.
class Lines {
 public:
  Lines(std::string_view text, bool hash_comments, std::size_t start = 0, int first_line = 1)
      : text_(text), pos_(start), line_(first_line - 1), hash_(hash_comments) {}

  //! Next line (possibly empty); false at end of text.
  bool next(std::string_view& out);
  //! Next line holding at least one token.
  bool next_content(std::string_view& out);
  int line() const { return line_; }
  std::size_t pos() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_;
  int line_;
  bool hash_;
};

//! The blank-separated tokens of s (into toks, cleared first).
void split(std::string_view s, std::vector<std::string_view>& toks);

//! Whole-token parses (an optional leading '+'); false on anything else, on overflow and on a double that
//! is out of range (1e400). "nan" and "inf" parse: the coordinate checks refuse them with their own message.
bool parse_double(std::string_view t, double& v);
bool parse_int(std::string_view t, long long& v);

//! t in single quotes, cut after 40 characters ("'abc'", "'aaaa...'").
std::string quote(std::string_view t);

//! ASCII lower case.
std::string lower(std::string s);

//! The Mesh of xyz (x y z per vertex) and tri (three corners per face), named after the file's stem.
Mesh assemble(const std::vector<double>& xyz, const std::vector<int>& tri, const std::string& path);

//! Fan-triangulates poly (corner indices, already checked) onto tri: (p0 p1 p2), (p0 p2 p3), ...
void fan(const std::vector<long long>& poly, std::vector<int>& tri);

//! Every count a file declares is checked against the bytes that follow before anything is allocated or looped
//! over: an entry takes at least min_bytes (a text value one character and one separator, a binary one its
//! size). A header that declares 10^12 entries so ends at once with an error instead of a hang or an allocation
//! failure. Subtracts what the entries take from bytes_left. \throw InputError at `line`, naming `what`.
void check_declared(const std::string& path, int line, unsigned long long count, std::size_t min_bytes,
                    std::size_t& bytes_left, const std::string& what);

//! \throw InputError "PATH: line LINE: vertex I: non-finite coordinate C" for the first non-finite of p[0..2].
void check_coordinates(const std::string& path, int line, long long i, const double* p);

//! A T read from unaligned bytes at p, in the host's byte order.
template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

//! The binary formats read and written here are little-endian and are loaded with memcpy.
//! \throw InputError "PATH: FORMAT needs a little-endian host" on any other host.
void require_little_endian_host(const std::string& path, const std::string& format);

//! Buffered text output: fmt formats doubles as the shortest string that reads back exactly, which makes the
//! text round trip lossless and the bytes deterministic.
class TextOut {
 public:
  explicit TextOut(std::ostream& os) : os_(os) {}
  ~TextOut() { flush(); }
  TextOut(const TextOut&) = delete;
  TextOut& operator=(const TextOut&) = delete;
  template <class... A>
  void put(fmt::format_string<A...> f, A&&... a) {
    fmt::format_to(std::back_inserter(buf_), f, std::forward<A>(a)...);
    if (buf_.size() > (1u << 20)) flush();
  }
  void flush();

 private:
  std::ostream& os_;
  fmt::memory_buffer buf_;
};

}  // namespace db::io
