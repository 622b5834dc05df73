#pragma once

#include <string>
#include <string_view>

namespace tocd::mocks::net {

/// Cuts newline-terminated lines off the front of a growing input buffer. Each byte is looked
/// at once: the scanner remembers how far the unfinished line has been searched, so a line that
/// arrives in many pieces costs time linear in its length, not in its length squared.
class LineScanner {
 public:
  /// Calls `on_line(line)` (without the '\n' and a '\r' before it) for each complete line at
  /// the front of `input`, then erases those lines from it. Stops early, returning false, when
  /// `on_line` returns false.
  template <class OnLine>
  bool take_lines(std::string& input, OnLine&& on_line) {
    std::size_t start = 0;
    bool go_on = true;
    while (go_on) {
      const auto nl = input.find('\n', scanned_);
      if (nl == std::string::npos) {
        scanned_ = input.size();
        break;
      }
      std::string_view line(input.data() + start, nl - start);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      start = scanned_ = nl + 1;
      go_on = on_line(line);
    }
    input.erase(0, start);
    scanned_ -= start;
    return go_on;
  }

  /// How many bytes of the unfinished line have been searched already.
  std::size_t scanned() const { return scanned_; }

 private:
  std::size_t scanned_ = 0;
};

}  // namespace tocd::mocks::net
