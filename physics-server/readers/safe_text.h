// Text from input files that reaches a terminal, a file name or the wire:
// printable UTF-8 checked, the rest shown escaped, names checked for paths.
#pragma once

#include <string>

namespace chainsim {

// valid UTF-8 with no control character (C0, DEL, C1)
bool is_printable_text(const std::string& s);
// s with each control character and each byte of invalid UTF-8 as \xNN, so
// a message never moves the cursor or breaks a line
std::string shown_text(const std::string& s);
// shown_text, and when longer than max_chars its start with
// "... (N bytes in all)": a message quoting a 50 MB cell stays a line
std::string shown_text_cut(const std::string& s, size_t max_chars = 600);
// a name that may be a file or directory name: 1 to 63 of letters, digits,
// '_', '-', '.', not starting with '.' or '-' (so never "..", never an option)
bool is_path_name(const std::string& s);
// what is_path_name asks, for messages
extern const char* const kPathNameRule;

}  // namespace chainsim
