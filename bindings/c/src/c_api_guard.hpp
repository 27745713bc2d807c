#pragma once
// The one place where C++ exceptions become ppohdem_status codes and a thread-local message
// (ppohdem.h: "No C++ exception crosses this boundary"); docs/fortran.md "The C API".
#include <exception>
#include <stdexcept>
#include <string>

#include "ppohdem/ppohdem.h"

namespace ppohdem::c_api {

/// A NULL pointer, a bad count or an unknown name passed by the caller.
struct ArgumentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// A stage called before its prerequisite.
struct StateError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// An output buffer smaller than the documented count.
struct BufferError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void set_last_error(const std::string& message);
ppohdem_status translate_current_exception(const char* function);

/// Runs body(); returns PPOHDEM_OK or the status of the exception it threw, with the message
/// "function: what".
template <class Body>
ppohdem_status guarded(const char* function, Body&& body) noexcept {
  try {
    body();
    set_last_error("");
    return PPOHDEM_OK;
  } catch (...) {
    return translate_current_exception(function);
  }
}

template <class T>
T& require(T* pointer, const char* what) {
  if (pointer == nullptr) throw ArgumentError(std::string(what) + " is NULL");
  return *pointer;
}

inline std::string require_text(const char* text, const char* what) {
  if (text == nullptr) throw ArgumentError(std::string(what) + " is NULL");
  return text;
}

inline void require_capacity(std::size_t given, std::size_t needed, const char* what) {
  if (given < needed) {
    throw BufferError(std::string(what) + " holds " + std::to_string(given) + " elements, " +
                      std::to_string(needed) + " needed");
  }
}

}  // namespace ppohdem::c_api
