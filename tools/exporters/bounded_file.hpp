// An output file that never grows past its limit, so that no firmware can fill the disk through
// a run's logs: of the write that would cross the limit, a text file keeps the whole lines that
// fit and then a note in its own comment syntax, a binary file the bytes that fit; everything
// after that is dropped and counted.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>

namespace sear {

class BoundedFile {
 public:
  // `note` is written once, at the limit, as the file's last line (empty for binary files).
  // Throws std::runtime_error naming the file if it cannot be created.
  BoundedFile(std::string path, std::uint64_t limit_bytes, std::string note);
  ~BoundedFile();
  BoundedFile(const BoundedFile&) = delete;
  BoundedFile& operator=(const BoundedFile&) = delete;

  void write(std::string_view bytes);
  // Pushes everything to the file; throws std::runtime_error naming it on a write error.
  void flush();
  const std::string& path() const { return path_; }
  bool truncated() const { return dropped_ > 0; }

 private:
  void spill();  // the buffer to the file

  static constexpr std::size_t kBufferBytes = 64 * 1024;
  std::string path_;
  std::unique_ptr<char[]> buffer_;  // bytes written but not yet handed to file_
  std::size_t buffered_ = 0;
  std::FILE* file_ = nullptr;       // unbuffered: every fwrite is a write(2)
  std::uint64_t limit_;
  std::string note_;
  std::uint64_t written_ = 0;
  std::uint64_t dropped_ = 0;
};

// The notes for text, CSV and VCD files, naming the limit.
std::string text_truncation_note(std::uint64_t limit_bytes);
std::string vcd_truncation_note(std::uint64_t limit_bytes);

}  // namespace sear
