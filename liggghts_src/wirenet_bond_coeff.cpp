/* WireNet: bond_coeff parser. Grammar in doc/bond_wirenet.md. */

#include "wirenet_bond_coeff.h"

#include <cerrno>
#include <cstdlib>
#include <stdexcept>

namespace WireNet {

namespace {

bool to_number(const std::string &s, double &v)
{
  if (s.empty()) return false;
  char *end = nullptr;
  errno = 0;
  v = std::strtod(s.c_str(), &end);
  return errno == 0 && end && *end == '\0';
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
  double number(const std::string &what)
  {
    const std::string s = word(what);
    double v;
    if (!to_number(s, v)) throw std::invalid_argument(what + " must be a number (got '" + s + "')");
    return v;
  }
  // "name value" pair where the name is fixed
  double keyed(const std::string &key, const std::string &context)
  {
    const std::string k = word(context + " " + key);
    if (k != key) throw std::invalid_argument(context + ": expected '" + key + "', got '" + k + "'");
    return number(context + " " + key);
  }
  bool next_is_number() const
  {
    double v;
    return !done() && to_number(a_[k_], v);
  }

 private:
  const std::vector<std::string> &a_;
  size_t k_ = 0;
};

bool is_wire_keyword(const std::string &w)
{
  return w == "family" || w == "area_factor" || w == "derived" || w == "slack";
}

void parse_wire(ArgCursor &c, BondTypeSpec &spec)
{
  WireLawParams &w = spec.wire;
  w.diameter = c.keyed("diameter", "wire");
  const std::string kw = c.word("wire 'curve'");
  if (kw != "curve") throw std::invalid_argument("wire: expected 'curve', got '" + kw + "'");
  std::vector<double> values;
  while (c.next_is_number()) values.push_back(c.number("curve value"));
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
    else if (key == "area_factor") w.area_factor = c.number("area_factor");
    else if (key == "derived") {
      w.derived = true;
      w.lambda_eps = c.keyed("lambda_eps", "derived");
      w.lambda_k = c.keyed("lambda_k", "derived");
      w.nu = c.keyed("nu", "derived");
    } else if (key == "slack") {
      w.slack = true;
      w.lambda_u = c.keyed("lambda_u", "slack");
      w.lambda_f = c.keyed("lambda_f", "slack");
      const double s = c.keyed("seed", "slack");
      if (s != (double)(long)s) throw std::invalid_argument("slack seed must be an integer (got " + std::to_string(s) + ")");
      w.seed = (long)s;
    } else {
      double ignored;
      if (to_number(key, ignored)) throw std::invalid_argument("unexpected number '" + key + "' after the wire options");
      throw std::invalid_argument("unknown wire keyword '" + key + "'");
    }
  }
  WireLaw check(w);  // validates the table and parameters
}

void parse_beam(ArgCursor &c, BondTypeSpec &spec)
{
  BeamLawParams &b = spec.beam;
  b.diameter = c.keyed("diameter", "beam");
  b.young = c.keyed("E", "beam");
  b.nu = c.keyed("nu", "beam");
  while (!c.done()) {
    const std::string key = c.word("keyword");
    if (key == "family") spec.family = c.word("family name");
    else if (key == "bending") b.bending = c.number("bending fraction");
    else if (key == "twist") b.twist = c.number("twist fraction");
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

}  // namespace

BondTypeSpec parse_bond_coeff(const std::vector<std::string> &args)
{
  ArgCursor c(args);
  BondTypeSpec spec;
  const std::string law = c.word("law (wire or beam)");
  if (law == "wire") {
    spec.kind = LawKind::WIRE;
    spec.family = "wire";
    parse_wire(c, spec);
  } else if (law == "beam") {
    spec.kind = LawKind::BEAM;
    spec.family = "beam";
    parse_beam(c, spec);
  } else {
    throw std::invalid_argument("unknown law '" + law + "' (expected wire or beam)");
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
                        (double)w.slack, w.lambda_u, w.lambda_f, (double)w.seed });
  } else if (kind == LawKind::BEAM) {
    const BeamLawParams &b = beam;
    v.insert(v.end(), { b.diameter, b.young, b.nu, b.bending, b.twist, (double)b.shear });
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
  } else if (s.kind == LawKind::BEAM) {
    BeamLawParams &b = s.beam;
    b.diameter = v.at(k++); b.young = v.at(k++); b.nu = v.at(k++);
    b.bending = v.at(k++); b.twist = v.at(k++); b.shear = (ShearModel)(int)v.at(k++);
  }
  return s;
}

}  // namespace WireNet
