// Errors: InputError is the one type for bad user input (file, field, value), thrown by the
// library and caught once in the CLI. Programmer errors use PGT_CHECK, which prints operands.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace pgt {

// `text` made safe for a one-line message: control characters (a NUL, a newline) become
// \uXXXX escapes and anything past `maxChars` is cut with "...". Keys and values of hostile
// files are echoed through this, so an error stays one short line. `keepNewlines` keeps
// '\n' (a compiler log in a message).
std::string printable(const std::string& text, size_t maxChars, bool keepNewlines = false);

// Bad input: names the file, the field (JSON pointer-like path or image texel) and the value.
class InputError : public std::runtime_error {
  public:
    InputError(std::string file, std::string field, std::string value, const std::string& message)
        : std::runtime_error(format(file, field, value, message)),
          file_(std::move(file)),
          field_(std::move(field)),
          value_(std::move(value)) {}

    const std::string& file() const { return file_; }
    const std::string& field() const { return field_; }
    const std::string& value() const { return value_; }

  private:
    static std::string format(const std::string& file, const std::string& field,
                              const std::string& value, const std::string& message) {
        // Long enough for any real field path or value, short enough for one line.
        constexpr size_t kMaxEcho = 120;
        std::ostringstream os;
        os << (file.empty() ? "<input>" : printable(file, 4 * kMaxEcho));
        if (!field.empty()) os << ": " << printable(field, kMaxEcho);
        if (!value.empty()) os << " = " << printable(value, kMaxEcho);
        os << ": " << printable(message, 64 * kMaxEcho, true);
        return os.str();
    }
    std::string file_, field_, value_;
};

// An output could not be written (exit status differs from bad input).
class OutputError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

namespace detail {
[[noreturn]] void checkFailed(const char* expr, const char* file, int line,
                              const std::string& values);
}

}  // namespace pgt

// Programmer-error checks that print both operands (pbrt-style).
#define PGT_CHECK(cond)                                                         \
    do {                                                                        \
        if (!(cond)) ::pgt::detail::checkFailed(#cond, __FILE__, __LINE__, ""); \
    } while (0)
#define PGT_CHECK_OP(a, op, b)                                                                \
    do {                                                                                      \
        auto pgt_a_ = (a);                                                                    \
        auto pgt_b_ = (b);                                                                    \
        if (!(pgt_a_ op pgt_b_)) {                                                            \
            std::ostringstream pgt_os_;                                                       \
            pgt_os_ << #a " = " << pgt_a_ << ", " #b " = " << pgt_b_;                         \
            ::pgt::detail::checkFailed(#a " " #op " " #b, __FILE__, __LINE__, pgt_os_.str()); \
        }                                                                                     \
    } while (0)
#define PGT_CHECK_EQ(a, b) PGT_CHECK_OP(a, ==, b)
#define PGT_CHECK_LT(a, b) PGT_CHECK_OP(a, <, b)
#define PGT_CHECK_LE(a, b) PGT_CHECK_OP(a, <=, b)
#define PGT_CHECK_GE(a, b) PGT_CHECK_OP(a, >=, b)
