#include "exporters/bounded_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace sear {

std::string text_truncation_note(std::uint64_t limit_bytes) {
  return fmt::format("# truncated: this file reached its limit of {} bytes (sear run --max-file-mb); the rest of the run "
                     "is not in it\n",
                     limit_bytes);
}

std::string vcd_truncation_note(std::uint64_t limit_bytes) {
  return fmt::format("$comment truncated: this file reached its limit of {} bytes (sear run --max-file-mb); the rest "
                     "of the run is not in it $end\n",
                     limit_bytes);
}

BoundedFile::BoundedFile(std::string path, std::uint64_t limit_bytes, std::string note)
    : path_(std::move(path)), limit_(limit_bytes), note_(std::move(note)) {
  file_ = std::fopen(path_.c_str(), "wb");
  if (!file_) throw std::runtime_error(fmt::format("{}: error: cannot write: {}", path_, std::strerror(errno)));
  // The run flushes on a wall-clock period (FlushClock); between flushes a busy file (a VCD takes
  // megabytes a simulated second) fills a 64 KiB buffer before it costs a write(2). The buffer
  // is this class's own, not stdio's: a UART capture writes a few bytes at a time, hundreds of
  // thousands of times a simulated second, and fwrite's own work per call was a third of that.
  buffer_ = std::make_unique<char[]>(kBufferBytes);
  std::setvbuf(file_, nullptr, _IONBF, 0);
}

BoundedFile::~BoundedFile() {
  if (!file_) return;
  spill();
  std::fclose(file_);
}

void BoundedFile::spill() {
  if (!buffered_) return;
  fwrite_unlocked(buffer_.get(), 1, buffered_, file_);
  buffered_ = 0;
}

void BoundedFile::write(std::string_view bytes) {
  if (dropped_ > 0) {
    dropped_ += bytes.size();
    return;
  }
  // Room is kept for the note, so that the file with its note stays within the limit.
  const std::uint64_t room = limit_ > note_.size() ? limit_ - note_.size() : 0;
  if (written_ + bytes.size() <= room) {
    if (buffered_ + bytes.size() > kBufferBytes) spill();
    if (bytes.size() > kBufferBytes) {
      fwrite_unlocked(bytes.data(), 1, bytes.size(), file_);  // one thread writes each file
    } else {
      std::memcpy(buffer_.get() + buffered_, bytes.data(), bytes.size());
      buffered_ += bytes.size();
    }
    written_ += bytes.size();
    return;
  }
  // A text file's writes may hold many lines (a waveform writes half a kilobyte at a time): the
  // whole lines that fit go in before the note. A file with no note (raw bytes, written in
  // blocks) is filled to its limit, as a byte at a time would fill it.
  std::size_t fits = 0;
  if (room > written_) {
    const std::string_view within = bytes.substr(0, static_cast<std::size_t>(room - written_));
    const std::size_t cut = note_.empty() ? within.size() - 1 : within.rfind('\n');
    if (cut != std::string_view::npos) fits = cut + 1;
  }
  spill();
  fwrite_unlocked(bytes.data(), 1, fits, file_);
  written_ += fits;
  std::fwrite(note_.data(), 1, note_.size(), file_);
  written_ += note_.size();
  dropped_ = bytes.size() - fits;
}

void BoundedFile::flush() {
  spill();
  if (std::fflush(file_) != 0 || std::ferror(file_))
    throw std::runtime_error(fmt::format("{}: error: write failed: {}", path_, std::strerror(errno)));
}

}  // namespace sear
