#pragma once
// Exceptions and the internal-invariant check shared by every module.

#include <stdexcept>
#include <string>

namespace quadcage {

/// The input cannot be used: unreadable file, bad format, or a mesh that the requested operation
/// does not accept (open, non-manifold, ...). The message names the file or element and says what
/// to do. The CLI maps it to exit code 3.
class InvalidInput : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A usage conflict found before any work: an output would replace an input (e.g. `layout D/cage.obj
/// -o D`). The message names both paths and says what to do. The CLI maps it to exit code 2.
class OutputConflict : public InvalidInput {
public:
    using InvalidInput::InvalidInput;
};

/// A resource the library needs could not be had from the system or a library it runs on: memory,
/// a device or a build of a backend (e.g. Embree could not create its device or build its BVH). Not
/// a problem of the input nor a bug in quadcage; retrying with more memory may help. The message
/// names the backend and the call that failed. The CLI maps it to exit code 1.
class ResourceError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A broken internal invariant (a bug in quadcage, not in the input). The CLI maps it to exit code 1.
class InternalError : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

namespace detail {
[[noreturn]] void fail_check(const char* expr, const char* file, int line, const std::string& msg);
}

}  // namespace quadcage

/// Internal invariant check; always on (also in release builds: these guard geometry that, if
/// wrong, would be written to disk as a silently broken layout).
#define QC_CHECK(cond, msg)                                                            \
    do {                                                                               \
        if (!(cond)) ::quadcage::detail::fail_check(#cond, __FILE__, __LINE__, (msg)); \
    } while (0)
