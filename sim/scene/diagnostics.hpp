// Errors found in user files, each with the file and line it came from, collected so that
// `sear check` can report all of them rather than stopping at the first.
#pragma once

#include <string>
#include <vector>

namespace sear {

struct Diagnostic {
  std::string file;
  int line = 0;  // 0 when the problem is the file as a whole (missing, unreadable)
  std::string message;

  // "file:line: error: message", the form compilers use, so editors can jump to it.
  std::string str() const;
};

class Diagnostics {
 public:
  void error(const std::string& file, int line, std::string message);
  bool ok() const { return items_.empty(); }
  const std::vector<Diagnostic>& all() const { return items_; }
  std::string joined() const;  // one diagnostic per line

 private:
  std::vector<Diagnostic> items_;
};

}  // namespace sear
