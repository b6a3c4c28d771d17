// Errors found in user files, each with the file and line it came from, collected so that
// `sear check` can report all of them rather than stopping at the first.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace sear {

struct Diagnostic {
  std::string file;
  int line = 0;  // 0 when the problem is the file as a whole (missing, unreadable)
  std::string message;
  bool warning = false;  // plausible but probably a mistake: the run goes ahead

  // "file:line: error: message" (or "warning:"), the form compilers use, so editors can jump to it.
  std::string str() const;
};

class Diagnostics {
 public:
  // Only the first errors are kept: a generated file with millions of mistakes should give a
  // screenful and a count, not gigabytes of text (and memory). Beyond this they are only counted.
  static constexpr std::size_t kMaxKept = 100;

  void error(const std::string& file, int line, std::string message);
  bool ok() const { return count_ == 0; }
  // Every error found, including those not kept.
  std::size_t count() const { return count_; }
  // The first kMaxKept errors, in the order found.
  const std::vector<Diagnostic>& all() const { return items_; }
  // True once no more errors are kept: costly details (suggestions) need not be worked out.
  bool full() const { return items_.size() >= kMaxKept; }
  // One diagnostic per line, then "... and N more errors" when some were not kept.
  std::string joined() const;

  // What loads but is probably not what was meant (a sensor metres outside its robot). Kept apart
  // from the errors: they do not stop a run, and ok() does not count them. The first kMaxKept.
  void warning(const std::string& file, int line, std::string message);
  const std::vector<Diagnostic>& warnings() const { return warnings_; }
  // One warning per line.
  std::string warnings_joined() const;

 private:
  std::vector<Diagnostic> items_;
  std::size_t count_ = 0;
  std::vector<Diagnostic> warnings_;
};

}  // namespace sear
