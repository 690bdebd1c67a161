#include "Options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace wirenet {

void Options::addNumber(const std::string& name, double def, const std::string& unit,
                        const std::string& help, Bound bound) {
    Spec s{Kind::Number, unit, help, fmt(def), ""};
    s.def = s.text;
    s.bound = bound;
    s.number = def;
    order_.push_back(name);
    specs_[name] = s;
}

void Options::addOptionalNumber(const std::string& name, const std::string& unit,
                                const std::string& help, Bound bound, const std::string& defText) {
    Spec s{Kind::OptionalNumber, unit, help, defText, ""};
    s.def = s.text;
    s.bound = bound;
    order_.push_back(name);
    specs_[name] = s;
}

bool parseFinite(const std::string& text, double& value) {
    if (text.empty()) return false;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (*end != '\0' || errno == ERANGE || !std::isfinite(v)) return false;
    value = v;
    return true;
}

void Options::addInt(const std::string& name, long def, long minValue, const std::string& help,
                     long maxValue) {
    Spec s{Kind::Int, "-", help, std::to_string(def), ""};
    s.def = s.text;
    s.integer = def;
    s.minInt = minValue;
    s.maxInt = maxValue;
    order_.push_back(name);
    specs_[name] = s;
}

void Options::addString(const std::string& name, const std::string& def, const std::string& help) {
    Spec s{Kind::String, "-", help, def, ""};
    s.def = s.text;
    order_.push_back(name);
    specs_[name] = s;
}

const Options::Spec& Options::spec(const std::string& name) const {
    auto it = specs_.find(name);
    if (it == specs_.end()) throw std::logic_error("undeclared option --" + name);
    return it->second;
}

void Options::assign(const std::string& name, Spec& s, const std::string& value) {
    const std::string opt = "--" + name;
    if (s.kind == Kind::String) {
        if (value.empty()) throw UsageError(opt + " must not be empty (got '')");
        s.text = value;
        return;
    }
    char* end = nullptr;
    errno = 0;
    if (s.kind == Kind::Int) {
        long v = std::strtol(value.c_str(), &end, 10);
        if (value.empty() || *end != '\0' || errno == ERANGE)
            throw UsageError(opt + " must be an integer (got " + value + ")");
        if (v < s.minInt)
            throw UsageError(opt + " must be >= " + std::to_string(s.minInt) + " (got " + value + ")");
        if (v > s.maxInt)
            throw UsageError(opt + " must be <= " + std::to_string(s.maxInt) + " (got " + value + ")");
        s.integer = v;
    } else {
        double v = 0;
        if (!parseFinite(value, v)) throw UsageError(opt + " must be a number (got " + value + ")");
        if (std::abs(v) > kMaxMagnitude) {
            if (s.bound == Bound::Any)
                throw UsageError(opt + " must be between -" + fmt(kMaxMagnitude) + " and " +
                                 fmt(kMaxMagnitude) + " (got " + value + ")");
            throw UsageError(opt + " must be <= " + fmt(kMaxMagnitude) + " (got " + value + ")");
        }
        if (s.bound == Bound::Positive && !(v > 0))
            throw UsageError(opt + " must be > 0 (got " + value + ")");
        if (s.bound == Bound::NonNegative && !(v >= 0))
            throw UsageError(opt + " must be >= 0 (got " + value + ")");
        s.number = v;
        s.set = true;
    }
    s.text = value;
}

bool Options::parse(const std::vector<std::string>& args) {
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--help" || a == "-h") return false;
        if (a.rfind("--", 0) != 0) throw UsageError("unexpected argument " + a);
        std::string name = a.substr(2), value;
        bool inlineValue = false;
        if (auto eq = name.find('='); eq != std::string::npos) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
            inlineValue = true;
        }
        auto it = specs_.find(name);
        if (it == specs_.end()) throw UsageError("unknown option --" + name);
        if (!inlineValue) {
            if (i + 1 >= args.size()) throw UsageError("--" + name + " needs a value (got nothing)");
            value = args[++i];
        }
        assign(name, it->second, value);
        it->second.given = true;
        given_ += (given_.empty() ? "--" : " --") + name + " " + value;
        givenPairs_.emplace_back(name, value);
    }
    return true;
}

std::string Options::givenExcept(const std::string& name) const {
    std::string s;
    for (const auto& kv : givenPairs_)
        if (kv.first != name) s += (s.empty() ? "--" : " --") + kv.first + " " + kv.second;
    return s;
}

double Options::num(const std::string& name) const { return spec(name).number; }
bool Options::isSet(const std::string& name) const { return spec(name).set; }
bool Options::wasGiven(const std::string& name) const { return spec(name).given; }
long Options::integer(const std::string& name) const { return spec(name).integer; }
const std::string& Options::str(const std::string& name) const { return spec(name).text; }

const std::string& Options::choice(const std::string& name, const std::vector<std::string>& words) const {
    const std::string& v = str(name);
    for (const auto& w : words)
        if (v == w) return v;
    std::string list = words.front();
    for (size_t i = 1; i < words.size(); ++i) list += (i + 1 == words.size() ? " or " : ", ") + words[i];
    throw UsageError("--" + name + " must be " + list + " (got " + v + ")");
}

ValueText Options::valueText() const {
    return [this](const std::string& name, double) { return str(name); };
}

std::string Options::help() const {
    std::ostringstream os;
    os << "usage: wirenet-gen " << sub_ << " [options] --out "
       << (sub_.rfind("shape", 0) == 0 ? "FILE.stl" : "PREFIX") << "\n";
    if (!summary_.empty()) os << summary_ << "\n";
    os << "\noptions (SI units):\n";
    for (const auto& name : order_) {
        const Spec& s = specs_.at(name);
        std::string left = "  --" + name + (s.kind == Kind::String ? " TEXT" : " VALUE");
        if (left.size() < 28) left.resize(28, ' ');
        os << left << " " << s.help;
        if (s.unit != "-" && !s.unit.empty()) os << " [" << s.unit << "]";
        os << " (default: " << s.def << ")\n";
    }
    os << std::string("  --help").append(20, ' ') << " this text\n";
    return os.str();
}

}  // namespace wirenet
