#pragma once

#include <string>
#include <string_view>

namespace tocd {

/// Text from outside (an instrument's identity, a file) made safe to store, print and put in
/// JSON: valid UTF-8 is kept, except control characters (C0 including ESC, DEL, C1), which
/// would let a device drive the terminal, and the bidirectional formatting characters (U+202E
/// and its kin), which reorder what a terminal shows; those and every byte of an invalid UTF-8
/// sequence become U+FFFD. Printable ASCII passes unchanged.
std::string printable_text(std::string_view raw);

}  // namespace tocd
