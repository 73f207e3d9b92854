// stickslip — internals shared by the bridge's C++ sources (not installed, not part of the C contract).
#ifndef STICKSLIP_BRIDGE_INTERNAL_HPP
#define STICKSLIP_BRIDGE_INTERNAL_HPP

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

}  // namespace stickslip::bridge

#endif
