/* WireNet: brake law. See wirenet_brake_law.h and doc/bond_wirenet.md ("The brake law"). */

#include "wirenet_brake_law.h"
#include "wirenet_checks.h"

#include <cmath>
#include <stdexcept>

namespace WireNet {

BrakeLaw::BrakeLaw(const BrakeLawParams &p) : p_(p)
{
  // every check is written so that nan fails it; isfinite refuses inf
  require(std::isfinite(p.force) && p.force > 0.0, "brake force must be a finite number > 0 (got " + fmt(p.force) + ")");
  require(std::isfinite(p.stroke) && p.stroke > 0.0,
          "brake stroke must be a finite number > 0 (got " + fmt(p.stroke) + ")");
  require(std::isfinite(p.stiffness) && p.stiffness > 0.0,
          "brake stiffness must be a finite number > 0 (got " + fmt(p.stiffness) + ")");
  k_lock_ = p.lock ? *p.lock : p.stiffness;
  // Unloading follows K from wherever the brake is: a lock-up stiffer than K would give back
  // more energy on unloading than the lock-up branch took (negative plastic work).
  require(std::isfinite(k_lock_) && k_lock_ > 0.0 && k_lock_ <= p.stiffness,
          "brake lock must be a finite number > 0 and <= the stiffness " + fmt(p.stiffness) +
          " (unloading follows the stiffness; got " + fmt(k_lock_) + ")");
  if (p.breaking)
    require(std::isfinite(*p.breaking) && *p.breaking > p.force,
            "brake break must be a finite number > the force " + fmt(p.force) + " (got " + fmt(*p.breaking) + ")");
  require(std::isfinite(p.damping) && p.damping >= 0.0,
          "brake damping must be a finite number >= 0 (got " + fmt(p.damping) + ")");

  u_act_ = p.force / p.stiffness;
  u_end_ = u_act_ + p.stroke;
  u_break_ = p.breaking ? u_end_ + (*p.breaking - p.force) / k_lock_ : INFINITY;
  // extreme ratios: the table's elongations must be finite and strictly increasing in doubles
  require(std::isfinite(u_act_) && u_act_ > 0.0,
          "brake force / stiffness = " + fmt(u_act_) + " m is not a usable elongation (force " + fmt(p.force) +
          ", stiffness " + fmt(p.stiffness) + ")");
  require(std::isfinite(u_end_) && u_end_ > u_act_,
          "brake stroke " + fmt(p.stroke) + " is lost to round-off against the elastic elongation force / stiffness = " +
          fmt(u_act_) + " m");
  if (p.breaking)
    require(std::isfinite(u_break_) && u_break_ > u_end_,
            "brake break " + fmt(*p.breaking) + " is lost to round-off: (break - force) / lock = " +
            fmt((*p.breaking - p.force) / k_lock_) + " m against the stroke's end " + fmt(u_end_) + " m");
  else
    require(std::isfinite(u_end_ + p.stroke) && p.force + k_lock_ * p.stroke > p.force,
            "brake lock " + fmt(k_lock_) + " is lost to round-off against the force " + fmt(p.force) +
            " over the stroke " + fmt(p.stroke) + " m");
}

WireLawParams BrakeLaw::envelope() const
{
  WireLawParams w;
  w.force_elongation = true;
  w.breakable = breakable();
  w.damping = p_.damping;
  w.strain = { u_act_, u_end_ };
  w.stress = { p_.force, p_.force };
  if (breakable()) {
    w.strain.push_back(u_break_);
    w.stress.push_back(*p_.breaking);
  } else {
    // any point of the lock-up line: the envelope continues along it without end
    w.strain.push_back(u_end_ + p_.stroke);
    w.stress.push_back(p_.force + k_lock_ * p_.stroke);
  }
  return w;
}

}  // namespace WireNet
