// Errors, version and provenance of the C API (ppohdem.h).
#include <cstring>
#include <filesystem>
#include <new>
#include <string>

#include "c_api_guard.hpp"
#include "ppohdem/build_info.hpp"
#include "ppohdem/error.hpp"
#include "ppohdem/provenance.hpp"

namespace ppohdem::c_api {
namespace {
thread_local std::string last_error;
}

void set_last_error(const std::string& message) { last_error = message; }
const char* last_error_c_str() { return last_error.c_str(); }

ppohdem_status translate_current_exception(const char* function) {
  const std::string prefix = std::string(function) + ": ";
  try {
    throw;
  } catch (const ArgumentError& e) {
    set_last_error(prefix + e.what());
    return PPOHDEM_ERR_ARGUMENT;
  } catch (const StateError& e) {
    set_last_error(prefix + e.what());
    return PPOHDEM_ERR_STATE;
  } catch (const BufferError& e) {
    set_last_error(prefix + e.what());
    return PPOHDEM_ERR_BUFFER;
  } catch (const InputError& e) {
    set_last_error(prefix + e.what());
    return PPOHDEM_ERR_INPUT;
  } catch (const std::filesystem::filesystem_error& e) {
    set_last_error(prefix + e.what());
    return PPOHDEM_ERR_IO;
  } catch (const std::bad_alloc&) {
    set_last_error(prefix + "out of memory");
    return PPOHDEM_ERR_INTERNAL;
  } catch (const std::exception& e) {
    set_last_error(prefix + e.what());
    return PPOHDEM_ERR_INTERNAL;
  } catch (...) {
    set_last_error(prefix + "unknown C++ exception");
    return PPOHDEM_ERR_INTERNAL;
  }
}

}  // namespace ppohdem::c_api

using namespace ppohdem::c_api;

extern "C" {

const char* ppohdem_last_error(void) { return last_error_c_str(); }

const char* ppohdem_version(void) { return ppohdem::build_info::kVersion; }

ppohdem_status ppohdem_provenance(char* buf, size_t size, size_t* needed) {
  return guarded(__func__, [&] {
    const std::string line = ppohdem::provenance_line();
    if (needed != nullptr) *needed = line.size() + 1;
    if (buf == nullptr && size == 0) return;
    if (buf == nullptr) throw ArgumentError("buf is NULL");
    require_capacity(size, line.size() + 1, "buf");
    std::memcpy(buf, line.c_str(), line.size() + 1);
  });
}

}  // extern "C"
