#pragma once
// Errors. Two kinds, told apart by type so the command line can map them to exit codes:
//   InputError    – the user's input is wrong (exit 1). Carries where: file:line:column.
//   InternalError – a broken invariant inside Littoral (exit 2). Raised by the CHECK macros.
#include <sstream>
#include <stdexcept>
#include <string>

namespace littoral {

// A place in an input file; line and column are 1-based, 0 means "unknown".
struct SourceLoc {
    std::string file;
    int line = 0;
    int column = 0;
    // "file:line:column", "file:line", "file" or "" depending on what is known.
    std::string str() const;
};

class InputError : public std::runtime_error {
public:
    explicit InputError(std::string what);
    InputError(SourceLoc where, std::string what);
    const SourceLoc& where() const { return where_; }
    // The message without the location prefix.
    const std::string& message() const { return message_; }

private:
    SourceLoc where_;
    std::string message_;
};

class InternalError : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

namespace detail {
[[noreturn]] void checkFailed(const char* file, int line, const std::string& what);
template <class A, class B>
[[noreturn]] void checkOpFailed(const char* file, int line, const char* expr, const A& a, const B& b) {
    std::ostringstream os;
    os << expr << " (with " << a << " vs " << b << ")";
    checkFailed(file, line, os.str());
}
}  // namespace detail

// A library's error text on one line, for a message of Littoral's: OpenImageIO returns a reader's
// errors as several lines (e.g. "Read error: hit end of file", "PNG read error: IDAT: ...", "PNG
// library error"); they are trimmed, repeats and empty lines dropped, and joined with "; ".
std::string libraryMessage(const std::string& text);

}  // namespace littoral

// Internal invariants: print the failing expression and both operands, throw InternalError.
#define LITTORAL_CHECK(cond) \
    do { if (!(cond)) ::littoral::detail::checkFailed(__FILE__, __LINE__, #cond); } while (0)
#define LITTORAL_CHECK_OP(a, op, b)                                                           \
    do {                                                                                      \
        const auto& lit_a_ = (a);                                                             \
        const auto& lit_b_ = (b);                                                             \
        if (!(lit_a_ op lit_b_))                                                              \
            ::littoral::detail::checkOpFailed(__FILE__, __LINE__, #a " " #op " " #b, lit_a_, lit_b_); \
    } while (0)
#define LITTORAL_CHECK_EQ(a, b) LITTORAL_CHECK_OP(a, ==, b)
#define LITTORAL_CHECK_NE(a, b) LITTORAL_CHECK_OP(a, !=, b)
#define LITTORAL_CHECK_LT(a, b) LITTORAL_CHECK_OP(a, <, b)
#define LITTORAL_CHECK_LE(a, b) LITTORAL_CHECK_OP(a, <=, b)
#define LITTORAL_CHECK_GT(a, b) LITTORAL_CHECK_OP(a, >, b)
#define LITTORAL_CHECK_GE(a, b) LITTORAL_CHECK_OP(a, >=, b)
