// stickslip — internals shared by the bridge's C++ sources (not installed, not part of the C contract).
#ifndef STICKSLIP_BRIDGE_INTERNAL_HPP
#define STICKSLIP_BRIDGE_INTERNAL_HPP

#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include "stickslip/bridge.h"

namespace stickslip::bridge {

// Turns whatever a Trilinos call threw (std::exception, NOX's `throw "NOX Error"`, anything else) into an
// sk_status with a message naming the operation. Used in the catch blocks of every extern "C" entry point.
inline sk_status status_from_exception(sk_status code, const char *operation, std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception &e) {
    return sk_error_set(code, "%s: %s", operation, e.what());
  } catch (const char *text) {
    return sk_error_set(code, "%s: %s", operation, text);
  } catch (...) {
    return sk_error_set(code, "%s: unknown exception", operation);
  }
}

// printf-style formatting into a std::string (numbers in %g: a residual of 3e-7 must not print as 0.000000)
inline std::string format(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
inline std::string format(const char *fmt, ...) {
  char text[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(text, sizeof text, fmt, args);
  va_end(args);
  return text;
}

// A read-only look at a linear system's owned rows (merged over ranks) and their summed values, for the condensation
// stage (condense.cpp) which works on the assembled operator. Valid until the pattern changes.
struct system_rows {
  int n = 0, n_nodal = 0;
  const int64_t *row_ptr = nullptr;        // owned rows, local index i = global row first_row + i
  const int *cols = nullptr;               // global, sorted within rows
  int first_row = 0, n_owned = 0;          // this rank's contiguous block of rows
  const double *owned_values = nullptr;    // their summed values (CSR order), after sk_linsys_assemble
  const int *row_offsets = nullptr;        // size + 1 entries: rank r owns [row_offsets[r], row_offsets[r+1])
};
system_rows rows_of(const sk_linear_system *sys);

}  // namespace stickslip::bridge

#endif
