// Bad user input and how its one-line messages show values. Shared by the option parser and
// the parameter types' validate(), which name the options they check (the parameter types stay
// free of the parser: a program that sets them itself gets the same checks).
#pragma once
#include <functional>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace wirenet {

// Bad user input. The message names the option and the value; main() prefixes
// "wirenet-gen SUB: error: " and exits with code 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Formats a number compactly (%.12g) for messages and headers.
std::string fmt(double v);

// How a message shows the value of option `name` (without the dashes): the command line passes
// the text as typed, so "--snap 0.70" is quoted as 0.70; a program that set the value gets fmt().
using ValueText = std::function<std::string(const std::string& name, double value)>;
inline std::string formatted(const std::string&, double value) { return fmt(value); }

// Throws "SMALL must be <= BIG (got s > b)" unless smallValue <= bigValue.
void requireLess(const std::string& small, double smallValue, const std::string& big, double bigValue);

// How messages name a panel's width and height: the panel subcommands' own options, or the
// expressions a fence module derives them from.
struct SideNames {
    std::string width = "--width", height = "--height";
};

// The value among `all` whose name (nameOf) is `text`, into `out`; false if none is (an
// option's choice: the enumerations name their values once, in their xxxName function).
template <typename E, std::size_t N>
bool parseByName(const std::string& text, const E (&all)[N], const char* (*nameOf)(E), E& out) {
    for (E c : all)
        if (text == nameOf(c)) {
            out = c;
            return true;
        }
    return false;
}

}  // namespace wirenet
