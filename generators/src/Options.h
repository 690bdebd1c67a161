// Command-line options of one wirenet-gen subcommand: declaration, parsing, validation, help.
#pragma once
#include <limits>
#include <map>
#include <string>
#include <vector>
#include <utility>

#include "Usage.h"

namespace wirenet {

enum class Bound { Any, Positive, NonNegative };

// Every number option must lie within +-kMaxMagnitude (1e9 in its SI unit): larger values are
// typing mistakes, and squares or cubes of them (masses, volumes) would overflow.
constexpr double kMaxMagnitude = 1e9;
// Largest integer option (node indices are ints).
constexpr long kMaxInt = 1000000000;

class Options {
public:
    explicit Options(std::string subcommand) : sub_(std::move(subcommand)) {}

    void addNumber(const std::string& name, double def, const std::string& unit,
                   const std::string& help, Bound bound = Bound::Positive);
    // A number that may stay unset (default printed as "unset").
    void addOptionalNumber(const std::string& name, const std::string& unit,
                           const std::string& help, Bound bound = Bound::Positive,
                           const std::string& defText = "unset");
    void addInt(const std::string& name, long def, long minValue, const std::string& help,
                long maxValue = kMaxInt);
    void addString(const std::string& name, const std::string& def, const std::string& help);
    void setSummary(const std::string& text) { summary_ = text; }

    // Parses "--name value" and "--name=value"; throws UsageError. Returns false on --help.
    bool parse(const std::vector<std::string>& args);

    double num(const std::string& name) const;
    bool isSet(const std::string& name) const;  // optional number given
    bool wasGiven(const std::string& name) const;  // any option given on the command line
    long integer(const std::string& name) const;
    const std::string& str(const std::string& name) const;
    // A word option's value; throws "--NAME must be a, b or c (got x)" unless one of `words`.
    const std::string& choice(const std::string& name, const std::vector<std::string>& words) const;
    // The values as typed, for the messages of the parameter types' validate(); it refers to
    // this Options, which must outlive it.
    ValueText valueText() const;
    std::string help() const;
    // "--width 3 --height 3 ..." as given, for file headers.
    const std::string& given() const { return given_; }
    // The same without one option (e.g. "out"), for messages about the values.
    std::string givenExcept(const std::string& name) const;

private:
    enum class Kind { Number, OptionalNumber, Int, String };
    struct Spec {
        Kind kind;
        std::string unit, help, text;  // text: current value as typed / default
        std::string def;              // default, for --help
        Bound bound = Bound::Any;
        double number = std::numeric_limits<double>::quiet_NaN();
        long integer = 0, minInt = 0, maxInt = kMaxInt;
        bool set = false, given = false;
    };
    const Spec& spec(const std::string& name) const;
    void assign(const std::string& name, Spec& s, const std::string& value);

    std::string sub_, summary_, given_;
    std::vector<std::string> order_;
    std::vector<std::pair<std::string, std::string>> givenPairs_;
    std::map<std::string, Spec> specs_;
};

// Parses a whole string as a finite number within +-kMaxMagnitude; false otherwise
// (strtod alone accepts "inf", "nan" and overflows to inf).
bool parseFinite(const std::string& text, double& value);

}  // namespace wirenet
