/* WireNet: bond_coeff parser. Grammar in doc/bond_wirenet.md. */

#include "wirenet_bond_coeff.h"
#include "wirenet_checks.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace WireNet {

namespace {

// What a word is: a finite number, a number strtod reads but that is not finite ("inf",
// "infinity", "nan" in any case and sign, or an overflow such as "1e999"), or text.
enum class Word { NUMBER, NONFINITE, TEXT };

Word classify(const std::string &s, double &v)
{
  if (s.empty()) return Word::TEXT;
  char *end = nullptr;
  v = std::strtod(s.c_str(), &end);
  if (!end || *end != '\0') return Word::TEXT;
  return std::isfinite(v) ? Word::NUMBER : Word::NONFINITE;
}

// Walks the argument list; every accessor names what it expected when it fails.
class ArgCursor {
 public:
  explicit ArgCursor(const std::vector<std::string> &a) : a_(a) {}
  bool done() const { return k_ >= a_.size(); }
  const std::string &peek() const { return a_[k_]; }
  std::string word(const std::string &what)
  {
    if (done()) throw std::invalid_argument("missing " + what);
    return a_[k_++];
  }
  // A number word. A non-finite one is refused here unless the caller checks the range itself
  // (finite = false): the law's check then names the range ("must be a finite number > 0 (got
  // inf)"), WireLaw and BeamLaw refuse every non-finite parameter.
  double number(const std::string &what, bool finite = true)
  {
    const std::string s = word(what);
    double v;
    const Word w = classify(s, v);
    if (w == Word::TEXT) throw std::invalid_argument(what + " must be a number (got '" + s + "')");
    if (w == Word::NONFINITE && finite) throw std::invalid_argument(what + " must be a finite number (got " + s + ")");
    return v;
  }
  // "name value" pair where the name is fixed
  double keyed(const std::string &key, const std::string &context, bool finite = true)
  {
    const std::string k = word(context + " " + key);
    if (k != key) throw std::invalid_argument(context + ": expected '" + key + "', got '" + k + "'");
    return number(context + " " + key, finite);
  }
  // a number word, finite or not (a curve takes "inf" as a value, which its law then refuses)
  bool next_is_number() const
  {
    double v;
    return !done() && classify(a_[k_], v) != Word::TEXT;
  }

 private:
  const std::vector<std::string> &a_;
  size_t k_ = 0;
};

bool is_wire_keyword(const std::string &w)
{
  return w == "family" || w == "area_factor" || w == "derived" || w == "slack" || w == "damping";
}

void parse_wire(ArgCursor &c, BondTypeSpec &spec)
{
  WireLawParams &w = spec.wire;
  w.diameter = c.keyed("diameter", "wire", false);
  const std::string kw = c.word("wire 'curve'");
  if (kw != "curve") throw std::invalid_argument("wire: expected 'curve', got '" + kw + "'");
  std::vector<double> values;
  while (c.next_is_number()) values.push_back(c.number("curve value", false));
  // A word where a strain or a stress is due (no value yet, or a stress missing) that is not an
  // option keyword is a mistyped number: name it rather than report a short curve.
  if (!c.done() && (values.empty() || values.size() % 2) && !is_wire_keyword(c.peek()))
    throw std::invalid_argument("wire curve value " + std::to_string(values.size() + 1) +
                                " must be a number (got '" + c.peek() + "')");
  if (values.empty()) throw std::invalid_argument("wire curve is missing (strain stress pairs after 'curve')");
  if (values.size() % 2) throw std::invalid_argument("wire curve has an odd number of values (" +
                                                     std::to_string(values.size()) + "); give strain stress pairs");
  for (size_t k = 0; k < values.size(); k += 2) {
    w.strain.push_back(values[k]);
    w.stress.push_back(values[k + 1]);
  }
  while (!c.done()) {
    const std::string key = c.word("keyword");
    if (key == "family") spec.family = c.word("family name");
    else if (key == "area_factor") w.area_factor = c.number("area_factor", false);
    else if (key == "damping") w.damping = c.number("wire damping", false);
    else if (key == "derived") {
      w.derived = true;
      w.lambda_eps = c.keyed("lambda_eps", "derived", false);
      w.lambda_k = c.keyed("lambda_k", "derived", false);
      w.nu = c.keyed("nu", "derived", false);
    } else if (key == "slack") {
      w.slack = true;
      w.lambda_u = c.keyed("lambda_u", "slack", false);
      w.lambda_f = c.keyed("lambda_f", "slack", false);
      const double s = c.keyed("seed", "slack", false);
      // |s| < 2^53: every such double that is an integer converts to long exactly
      if (!std::isfinite(s) || std::fabs(s) >= 9007199254740992.0 || s != std::floor(s))
        throw std::invalid_argument("slack seed must be an integer (got " + fmt(s) + ")");
      w.seed = (long)s;
    } else {
      double ignored;
      if (classify(key, ignored) != Word::TEXT) throw std::invalid_argument("unexpected number '" + key + "' after the wire options");
      throw std::invalid_argument("unknown wire keyword '" + key + "'");
    }
  }
  WireLaw check(w);  // validates the table and parameters
}

void parse_beam(ArgCursor &c, BondTypeSpec &spec)
{
  BeamLawParams &b = spec.beam;
  const std::string shape = c.word("beam 'diameter' or 'section'");
  if (shape == "diameter") {
    b.diameter = c.number("beam diameter", false);
  } else if (shape == "section") {
    // section A IY IZ J orient X Y Z
    b.section = true;
    b.area = c.number("beam section A", false);
    b.iy = c.number("beam section IY", false);
    b.iz = c.number("beam section IZ", false);
    b.torsion = c.number("beam section J", false);
    const std::string o = c.word("beam 'orient' (after section A IY IZ J)");
    if (o != "orient") throw std::invalid_argument("beam section: expected 'orient' after A IY IZ J, got '" + o + "'");
    b.orient[0] = c.number("beam orient X", false);
    b.orient[1] = c.number("beam orient Y", false);
    b.orient[2] = c.number("beam orient Z", false);
  } else {
    throw std::invalid_argument("beam: expected 'diameter' or 'section', got '" + shape + "'");
  }
  b.young = c.keyed("E", "beam", false);
  b.nu = c.keyed("nu", "beam", false);
  while (!c.done()) {
    const std::string key = c.word("keyword");
    if (key == "family") spec.family = c.word("family name");
    else if (key == "bending") b.bending = c.number("beam bending fraction", false);
    else if (key == "twist") {
      // internally twist < 0 means "not given" (= bending): an explicit value must be >= 0
      b.twist = c.number("beam twist fraction", false);
      if (!(std::isfinite(b.twist) && b.twist >= 0.0))
        throw std::invalid_argument("beam twist fraction must be a finite number >= 0 (got " + fmt(b.twist) + ")");
    }
    else if (key == "strength") {
      b.strength = true;
      b.sigma_t = c.number("beam strength SIGMA_T", false);
      b.tau_c = c.number("beam strength TAU_C", false);
    } else if (key == "damping") b.damping = c.number("beam damping", false);
    else if (key == "shear") {
      const std::string m = c.word("shear model (eb or pb)");
      if (m == "eb") b.shear = ShearModel::EULER_BERNOULLI;
      else if (m == "pb") b.shear = ShearModel::PARALLEL_BOND;
      else throw std::invalid_argument("beam shear must be eb or pb (got '" + m + "')");
    } else {
      throw std::invalid_argument("unknown beam keyword '" + key + "'");
    }
  }
  BeamLaw check(b);  // validates the parameters
}

// `brake force F_ACT stroke S stiffness K [lock K_LOCK] [break F_BREAK] [family NAME]
// [damping ZETA]`: keyword-value pairs in any order, each at most once.
void parse_brake(ArgCursor &c, BondTypeSpec &spec)
{
  BrakeLawParams &b = spec.brake;
  std::vector<std::string> seen;
  while (!c.done()) {
    const std::string key = c.word("keyword");
    for (const std::string &s : seen)
      if (s == key) throw std::invalid_argument("brake " + key + " is given twice");
    seen.push_back(key);
    if (key == "force") b.force = c.number("brake force", false);
    else if (key == "stroke") b.stroke = c.number("brake stroke", false);
    else if (key == "stiffness") b.stiffness = c.number("brake stiffness", false);
    else if (key == "lock") b.lock = c.number("brake lock", false);
    else if (key == "break") b.breaking = c.number("brake break", false);
    else if (key == "damping") b.damping = c.number("brake damping", false);
    else if (key == "family") spec.family = c.word("family name");
    else {
      double ignored;
      if (classify(key, ignored) != Word::TEXT)
        throw std::invalid_argument("unexpected number '" + key + "' in the brake options (a keyword is due)");
      throw std::invalid_argument("unknown brake keyword '" + key + "'");
    }
  }
  for (const char *required : { "force", "stroke", "stiffness" }) {
    bool found = false;
    for (const std::string &s : seen) found = found || s == required;
    if (!found)
      throw std::invalid_argument(std::string("missing brake ") + required +
                                  " (brake force F_ACT stroke S stiffness K are required)");
  }
  BrakeLaw check(b);  // validates the parameters
  WireLaw envelope(check.envelope());
}

}  // namespace

BondTypeSpec parse_bond_coeff(const std::vector<std::string> &args)
{
  ArgCursor c(args);
  BondTypeSpec spec;
  const std::string law = c.word("law (wire, beam or brake)");
  if (law == "wire") {
    spec.kind = LawKind::WIRE;
    spec.family = "wire";
    parse_wire(c, spec);
  } else if (law == "beam") {
    spec.kind = LawKind::BEAM;
    spec.family = "beam";
    parse_beam(c, spec);
  } else if (law == "brake") {
    spec.kind = LawKind::BRAKE;
    spec.family = "brake";
    parse_brake(c, spec);
  } else {
    throw std::invalid_argument("unknown law '" + law + "' (expected wire, beam or brake)");
  }
  return spec;
}

std::vector<double> BondTypeSpec::serialize() const
{
  std::vector<double> v;
  v.push_back((double)kind);
  if (kind == LawKind::WIRE) {
    const WireLawParams &w = wire;
    v.insert(v.end(), { w.diameter, w.area_factor, (double)w.strain.size() });
    v.insert(v.end(), w.strain.begin(), w.strain.end());
    v.insert(v.end(), w.stress.begin(), w.stress.end());
    v.insert(v.end(), { (double)w.derived, w.lambda_eps, w.lambda_k, w.nu,
                        (double)w.slack, w.lambda_u, w.lambda_f, (double)w.seed, w.damping });
  } else if (kind == LawKind::BEAM) {
    const BeamLawParams &b = beam;
    v.insert(v.end(), { b.diameter, b.young, b.nu, b.bending, b.twist, (double)b.shear,
                        (double)b.strength, b.sigma_t, b.tau_c, b.damping });
    if (b.section)  // only then: a circular type's record is the one of files before sections
      v.insert(v.end(), { 1.0, b.area, b.iy, b.iz, b.torsion, b.orient[0], b.orient[1], b.orient[2] });
  } else if (kind == LawKind::BRAKE) {
    const BrakeLawParams &b = brake;
    v.insert(v.end(), { b.force, b.stroke, b.stiffness, (double)b.lock.has_value(), b.lock.value_or(0.0),
                        (double)b.breaking.has_value(), b.breaking.value_or(0.0), b.damping });
  }
  return v;
}

BondTypeSpec BondTypeSpec::deserialize(const std::vector<double> &v, const std::string &family)
{
  BondTypeSpec s;
  s.family = family;
  size_t k = 0;
  s.kind = (LawKind)(int)v.at(k++);
  if (s.kind == LawKind::WIRE) {
    WireLawParams &w = s.wire;
    w.diameter = v.at(k++);
    w.area_factor = v.at(k++);
    const size_t n = (size_t)v.at(k++);
    w.strain.assign(v.begin() + k, v.begin() + k + n); k += n;
    w.stress.assign(v.begin() + k, v.begin() + k + n); k += n;
    w.derived = v.at(k++) != 0.0;
    w.lambda_eps = v.at(k++); w.lambda_k = v.at(k++); w.nu = v.at(k++);
    w.slack = v.at(k++) != 0.0;
    w.lambda_u = v.at(k++); w.lambda_f = v.at(k++); w.seed = (long)v.at(k++);
    if (k < v.size()) w.damping = v.at(k++);  // absent from restart files before damping
  } else if (s.kind == LawKind::BEAM) {
    BeamLawParams &b = s.beam;
    b.diameter = v.at(k++); b.young = v.at(k++); b.nu = v.at(k++);
    b.bending = v.at(k++); b.twist = v.at(k++); b.shear = (ShearModel)(int)v.at(k++);
    if (k < v.size()) {  // absent from restart files before strength and damping
      b.strength = v.at(k++) != 0.0;
      b.sigma_t = v.at(k++); b.tau_c = v.at(k++); b.damping = v.at(k++);
    }
    if (k < v.size()) {  // a general section
      b.section = v.at(k++) != 0.0;
      b.area = v.at(k++); b.iy = v.at(k++); b.iz = v.at(k++); b.torsion = v.at(k++);
      for (int c = 0; c < 3; c++) b.orient[c] = v.at(k++);
    }
  } else if (s.kind == LawKind::BRAKE) {
    BrakeLawParams &b = s.brake;
    b.force = v.at(k++); b.stroke = v.at(k++); b.stiffness = v.at(k++);
    if (v.at(k++) != 0.0) b.lock = v.at(k);
    ++k;
    if (v.at(k++) != 0.0) b.breaking = v.at(k);
    ++k;
    b.damping = v.at(k++);
  } else if (s.kind != LawKind::NONE) {
    throw std::invalid_argument("unknown law in the restart file");
  }
  return s;
}

}  // namespace WireNet
