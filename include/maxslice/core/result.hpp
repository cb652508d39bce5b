#pragma once

#include <expected>
#include <string>
#include <utility>

namespace maxslice::core {

/// What kind of failure an Error is; the CLI maps it to an exit code.
enum class ErrorCode {
    kInvalidInput,  ///< The input is malformed, invalid or cannot be sliced (exit 2).
    kIo,            ///< A file could not be opened, read or written (exit 2).
    kUnsupported,   ///< A format or feature this build does not handle (exit 2).
    kCancelled,     ///< The caller cancelled the job (exit 2).
    kInternal,      ///< A bug in maxslice (exit 1).
};

/// A failure a person can act on: a message and where it happened ("layer 132, region 3").
struct Error {
    ErrorCode code = ErrorCode::kInternal;
    std::string message;
    std::string context;

    /// One line: "context: message", or the message alone when there is no context.
    [[nodiscard]] std::string describe() const {
        return context.empty() ? message : context + ": " + message;
    }
};

/// Stage functions return a value or an Error; exceptions do not cross module boundaries.
template <class T>
using Result = std::expected<T, Error>;

/// Shorthand for returning an error from a function that returns Result<T>.
[[nodiscard]] inline std::unexpected<Error> fail(ErrorCode code, std::string message,
                                                 std::string context = {}) {
    return std::unexpected(Error{code, std::move(message), std::move(context)});
}

/// Adds context to an error on its way up ("file foo.stl" + "line 12: bad number").
[[nodiscard]] inline Error with_context(Error error, const std::string& outer) {
    error.context = error.context.empty() ? outer : outer + ", " + error.context;
    return error;
}

}  // namespace maxslice::core
