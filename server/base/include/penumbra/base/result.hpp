#pragma once

#include <string>
#include <utility>
#include <variant>

#include "penumbra/base/assert.hpp"
#include "penumbra/base/error_code.hpp"

namespace penumbra::base {

// Why something failed, for untrusted input (files, messages, parameters). `code` is what kind of
// failure it is (error_code.hpp), `message` a sentence for a person, `where` the file:offset,
// field or JSON pointer that was wrong.
struct Error {
    ErrorCode code = ErrorCode::internal_error;
    std::string message;
    std::string where;

    // "where: message [code]", the form printed by the CLI and logged by the server.
    [[nodiscard]] std::string to_string() const;
};

inline Error make_error(ErrorCode code, std::string message, std::string where = {}) {
    return Error{code, std::move(message), std::move(where)};
}

// A value or the Error that prevented it. GCC 12 ships std::expected only for C++23, so the
// project keeps this small equivalent.
template <class T>
class [[nodiscard]] Result {
public:
    Result(T value)
        : state_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit by design

    Result(Error error)
        : state_(std::in_place_index<1>, std::move(error)) {}  // NOLINT

    [[nodiscard]] bool ok() const { return state_.index() == 0; }

    explicit operator bool() const { return ok(); }

    T& value() & {
        PENUMBRA_ASSERT(ok(), "Result::value() on an error");
        return std::get<0>(state_);
    }

    const T& value() const& {
        PENUMBRA_ASSERT(ok(), "Result::value() on an error");
        return std::get<0>(state_);
    }

    T&& value() && {
        PENUMBRA_ASSERT(ok(), "Result::value() on an error");
        return std::get<0>(std::move(state_));
    }

    T* operator->() { return &value(); }

    const T* operator->() const { return &value(); }

    T& operator*() & { return value(); }

    const T& operator*() const& { return value(); }

    [[nodiscard]] const Error& error() const {
        PENUMBRA_ASSERT(!ok(), "Result::error() on a value");
        return std::get<1>(state_);
    }

private:
    std::variant<T, Error> state_;
};

// Result<void>: success or an Error.
struct Ok {};

using Status = Result<Ok>;

}  // namespace penumbra::base
