// The error channel of robotica_native's plain C interface: the caller's buffer receives the
// message of a C++ exception, truncated and NUL-terminated.
#ifndef ROBOTICA_NATIVE__C_ERROR_HPP_
#define ROBOTICA_NATIVE__C_ERROR_HPP_

#include <cstddef>
#include <cstring>
#include <exception>

inline void copy_message(const char * what, char * error, long error_size)
{
  if (error != nullptr && error_size > 0) {
    std::strncpy(error, what, static_cast<std::size_t>(error_size - 1));
    error[error_size - 1] = '\0';
  }
}

// Return make() (a new object), or NULL with the message of the exception it threw in error.
template<class Make>
void * new_or_report(Make make, char * error, long error_size)
{
  try {
    return make();
  } catch (const std::exception & e) {
    copy_message(e.what(), error, error_size);
  } catch (...) {
    copy_message("unknown C++ exception", error, error_size);
  }
  return nullptr;
}

#endif  // ROBOTICA_NATIVE__C_ERROR_HPP_
