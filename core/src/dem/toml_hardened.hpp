#pragma once
// toml++ 3.3.0 (Debian bookworm), made safe on malformed input. Private to ppohdem_core: include
// this instead of <toml++/toml.h>, and only from ONE translation unit (scene.cpp), because the
// macros below change the bodies of toml++'s inline functions (two different bodies in two
// translation units would break the one-definition rule).
//
// Fuzzing found three reachable failures inside toml++ 3.3.0 (docs/reliability.md, findings 4-6):
//  - parse_key() and parse_value() check preconditions the parser itself can violate (`[#`,
//    `[[[1]]]`, `x = [0,}]`) with TOML_ASSERT_ASSUME: assert() in a debug build (abort), and
//    __builtin_assume(false) in a clang release build (undefined behaviour). Fixed upstream in
//    marzer/tomlplusplus PR #301 and later, not in the Debian package.
//    Here: NDEBUG is lifted around the include so TOML_ASSERT_ASSUME is TOML_ASSERT, and
//    TOML_ASSERT throws TomlInvariantViolation, which read_scene turns into an InputError.
//    Throwing is safe at those two sites: parse_key()/parse_value() are not noexcept and are
//    reached only from toml::parse*, whose exceptions (parse_error) take the same path.
//  - is_non_ascii_horizontal_whitespace() reaches TOML_UNREACHABLE for some non-ASCII code
//    points (upstream #295, PR #305). TOML_UNREACHABLE cannot be redefined, so read_scene never
//    hands toml++ a non-ASCII byte outside a comment (ascii_outside_comments below).
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace ppohdem::dem::detail {

/// A toml++ internal precondition failed: the input is malformed in a way toml++ 3.3.0 does
/// not report itself.
struct TomlInvariantViolation : std::logic_error {
  using std::logic_error::logic_error;
};

[[noreturn]] inline void toml_invariant_failed(const char* condition) {
  std::string message = "malformed TOML (toml++ parser precondition failed: ";
  message.append(condition).append(")");
  throw TomlInvariantViolation(message);
}

/// Position (1-based line and column) of the first byte >= 0x80 that is not inside a TOML
/// comment, or line 0 if there is none. Strings are tracked (basic "..." with escapes,
/// literal '...', and the multi-line forms) so that a '#' inside a string does not start a
/// comment. Non-ASCII text is therefore allowed in comments only, where toml++ does not test
/// it for whitespace.
struct NonAsciiByte {
  std::size_t line = 0;
  std::size_t column = 0;
  unsigned byte = 0;
};

inline NonAsciiByte first_non_ascii_outside_comments(std::string_view text) {
  enum class State { code, comment, basic, literal, basic_multi, literal_multi };
  State state = State::code;
  std::size_t line = 1;
  std::size_t column = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    ++column;
    const auto starts = [&](std::string_view token) { return text.substr(i, token.size()) == token; };
    if (c == '\n') {
      ++line;
      column = 0;
      if (state == State::comment) state = State::code;
      // A single-line string cannot span lines; toml++ reports that itself. Reset so the scan
      // stays in step with it.
      if (state == State::basic || state == State::literal) state = State::code;
      continue;
    }
    if (static_cast<unsigned char>(c) >= 0x80 && state != State::comment) {
      return {line, column, static_cast<unsigned char>(c)};
    }
    switch (state) {
      case State::code:
        if (c == '#') {
          state = State::comment;
        } else if (starts("\"\"\"")) {
          state = State::basic_multi;
          i += 2;
          column += 2;
        } else if (starts("'''")) {
          state = State::literal_multi;
          i += 2;
          column += 2;
        } else if (c == '"') {
          state = State::basic;
        } else if (c == '\'') {
          state = State::literal;
        }
        break;
      case State::basic:
      case State::basic_multi:
        if (c == '\\') {  // an escape: the next character is part of the string
          if (i + 1 < text.size() && text[i + 1] != '\n') {
            ++i;
            ++column;
          }
        } else if (state == State::basic && c == '"') {
          state = State::code;
        } else if (state == State::basic_multi && starts("\"\"\"")) {
          state = State::code;
          i += 2;
          column += 2;
        }
        break;
      case State::literal:
        if (c == '\'') state = State::code;
        break;
      case State::literal_multi:
        if (starts("'''")) {
          state = State::code;
          i += 2;
          column += 2;
        }
        break;
      case State::comment:
        break;
    }
  }
  return {};
}

}  // namespace ppohdem::dem::detail

#pragma push_macro("NDEBUG")
#undef NDEBUG
#define TOML_ASSERT(expr) \
  ((expr) ? static_cast<void>(0) : ::ppohdem::dem::detail::toml_invariant_failed(#expr))
#include <toml++/toml.h>
#pragma pop_macro("NDEBUG")
