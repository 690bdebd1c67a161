// Command-line options of one wirenet-gen subcommand: declaration, parsing, validation, help.
#pragma once
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace wirenet {

// Bad user input. The message names the option and the value; main() prefixes
// "wirenet-gen SUB: error: " and exits with code 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum class Bound { Any, Positive, NonNegative };

class Options {
public:
    explicit Options(std::string subcommand) : sub_(std::move(subcommand)) {}

    void addNumber(const std::string& name, double def, const std::string& unit,
                   const std::string& help, Bound bound = Bound::Positive);
    // A number that may stay unset (default printed as "unset").
    void addOptionalNumber(const std::string& name, const std::string& unit,
                           const std::string& help, Bound bound = Bound::Positive,
                           const std::string& defText = "unset");
    void addInt(const std::string& name, long def, long minValue, const std::string& help);
    void addString(const std::string& name, const std::string& def, const std::string& help);
    void setSummary(const std::string& text) { summary_ = text; }

    // Parses "--name value" and "--name=value"; throws UsageError. Returns false on --help.
    bool parse(const std::vector<std::string>& args);

    double num(const std::string& name) const;
    bool isSet(const std::string& name) const;  // optional number given
    bool wasGiven(const std::string& name) const;  // any option given on the command line
    long integer(const std::string& name) const;
    const std::string& str(const std::string& name) const;
    std::string help() const;
    // "--width 3 --height 3 ..." as given, for file headers.
    const std::string& given() const { return given_; }

    // Checks used by the generators: throw UsageError naming the option.
    void requireLess(const std::string& small, double smallValue, const std::string& big,
                     double bigValue) const;

private:
    enum class Kind { Number, OptionalNumber, Int, String };
    struct Spec {
        Kind kind;
        std::string unit, help, text;  // text: current value as typed / default
        std::string def;              // default, for --help
        Bound bound = Bound::Any;
        double number = std::numeric_limits<double>::quiet_NaN();
        long integer = 0, minInt = 0;
        bool set = false, given = false;
    };
    const Spec& spec(const std::string& name) const;
    void assign(const std::string& name, Spec& s, const std::string& value);

    std::string sub_, summary_, given_;
    std::vector<std::string> order_;
    std::map<std::string, Spec> specs_;
};

// Formats a number compactly (%.12g) for messages and headers.
std::string fmt(double v);

}  // namespace wirenet
