// Private to src/io: the per-format readers and writers behind readMesh/writeMesh, and the
// small text and error helpers they share. Not installed.
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/mesh_io.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace pcl {
namespace patchdict {
namespace io_detail {

// ---------------------------------------------------------------- readers
// Each reader gets the whole file in `bytes` (read once by readMesh) and fills mesh and info, or
// throws Error. `path` is only used in messages. The mesh is assigned only on success.
void readPly(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info);
void readObj(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info);
void readOff(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info);
void readStl(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info);
// PCL decodes PCD files from the path; `bytes` are only checked first (PCL crashes on some
// malformed headers and reads garbage ascii values as 0).
void readPcd(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info);

// ---------------------------------------------------------------- writers
// Stream formats return the file's bytes; writeMesh puts them in place atomically. The mesh has
// been validated (finite coordinates, face indices in range) before these are called.
std::string writePly(const TriangleMesh& mesh, const WriteOptions& options);
std::string writeObj(const TriangleMesh& mesh, const WriteOptions& options);
std::string writeOff(const TriangleMesh& mesh, const WriteOptions& options);
std::string writeStl(const TriangleMesh& mesh, const WriteOptions& options);
// PCL writes PCD files itself: writes to `file_path` (the temporary file); `target` names the
// file in error messages.
void writePcd(const std::string& target, const std::string& file_path, const TriangleMesh& mesh,
              const WriteOptions& options);

// ---------------------------------------------------------------- shared helpers
/** Throws Error("cannot read '<path>': <what>"). */
[[noreturn]] void failRead(const std::string& path, const std::string& what);
/** Throws Error("cannot read '<path>': line <line>: <what>"). */
[[noreturn]] void failReadLine(const std::string& path, std::size_t line, const std::string& what);

/** A token from the file, quoted and shortened for an error message (never contains a newline). */
std::string quoted(std::string_view token);

/** Parses a whole token as a real number ('+' sign, nan, inf accepted; over/underflow gives
  * ±inf / ±0 as strtod would). False if the token is not entirely a number. */
bool parseDouble(std::string_view token, double& value);
/** Same, rounding the decimal straight to float (one rounding, as a float32 field demands). */
bool parseFloat(std::string_view token, float& value);
/** Parses a whole token as a signed integer. */
bool parseInt(std::string_view token, std::int64_t& value);

/** Appends the shortest text that reads back to exactly `value`. */
void appendNumber(std::string& out, double value);
void appendNumber(std::string& out, float value);
/** "x y z" in the same shortest round-trip form, then `end` (e.g. '\n'). */
void appendVector(std::string& out, const Eigen::Vector3d& v, char end = '\n');

/** True if the double survives a trip through float unchanged (and is finite). */
bool isFloatExact(double value);

/** Text cursor over a buffer: whitespace-separated tokens, line numbers for messages. */
class TextCursor {
public:
  /** `comment` (e.g. '#'), when not 0, starts a comment that runs to the end of its line. */
  explicit TextCursor(std::string_view text, std::size_t first_line = 1, char comment = 0)
      : pos_(text.data()), end_(text.data() + text.size()), line_(first_line), comment_(comment) {}

  /** Next token, crossing line breaks. False at the end of the buffer. */
  bool next(std::string_view& token);
  /** Next token on the current line only; false (without moving past it) at end of line. */
  bool nextOnLine(std::string_view& token);
  /** Skips the rest of the current line, including its line break. */
  void skipLine();
  /** Line number of the cursor (of the last token read, once a token has been read). */
  std::size_t line() const { return line_; }
  bool atEnd() const { return pos_ == end_; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - pos_); }

private:
  /** The token starting at pos_ (which is not blank, not a line break). */
  std::string_view takeToken();

  const char* pos_;
  const char* end_;
  std::size_t line_;
  char comment_;
};

}  // namespace io_detail
}  // namespace patchdict
}  // namespace pcl
