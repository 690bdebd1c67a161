/* WireNet: bond_style wirenet, remote bonds between the node spheres of a wire net.
   Laws per bond type: `wire` (tension-only elasto-plastic), `beam` (corotational parallel
   bond) and `brake` (a rope brake: a wire bond with a force-elongation envelope). See
   doc/bond_wirenet.md. */

#ifdef BOND_CLASS

BondStyle(wirenet,BondWirenet)

#else

#ifndef LMP_BOND_WIRENET_H
#define LMP_BOND_WIRENET_H

#include <memory>
#include <string>
#include <vector>

#include "bond.h"
#include "wirenet_beam_law.h"
#include "wirenet_bond_coeff.h"
#include "wirenet_wire_law.h"

namespace LAMMPS_NS {

class BondWirenet : public Bond {
 public:
  BondWirenet(class LAMMPS *);
  ~BondWirenet();
  void init();
  void init_style();
  void compute(int, int);
  void settings(int, char **);
  void coeff(int, char **);
  double equilibrium_distance(int) { return 0.0; }
  void write_restart(FILE *);
  void read_restart(FILE *);
  double single(int, double, int, int, double &);
  double memory_usage();

  // Output of one bond (i local, slot m, partner j): false if it is broken or not initialised.
  struct BondState { double length0, length, tension, shear, moment; };
  bool bond_state(int i, int m, int j, BondState &s) const;
  const std::string &family(int type) const { return specs[type].family; }
  // Bring the plastic-work tally of fix wirenet/bonds up to the bonds' state: adds the change of
  // this rank's sum of WireLaw::plastic_work since the last call (called before the tally is
  // read or written; a no-op when no compute() ran in between).
  void sync_plastic();
  // Squared angular frequencies (translation, rotation) of the stiffest bond of this rank's
  // list, as the stable step estimate counts them (report_timestep); 0 without bonds. Valid
  // after the first force evaluation of a run (the list is built there).
  void stable_frequencies(double w2[2]) const;
  bool list_built() const { return list_version >= 0; }

 private:
  // The intact local bonds, rebuilt whenever atoms or bond slots change: wire bonds as entries
  // into the history, beam bonds (records set at their first run, constant afterwards) as
  // copies of their constants, two bonds per entry, one per SIMD lane: first the circular
  // sections (ncircular pairs), then the general sections, whose anisotropic constants are in
  // section_list (same order). A pair with one bond (n = 1, the last of each group) repeats it
  // in lane 1: computed, not applied.
  struct Entry { int i, j, type, m; double *h; };
  // a wire bond with the constants of its envelope and damping (built with the list)
  struct WireEntry : Entry { WireNet::WireConst k; double zeta; const WireNet::WireLaw *law; };
  // type: the bond type (energy tallies per type)
  struct BeamPair { WireNet::BeamConst<WireNet::Lanes> c; int i[2], j[2], m[2], type[2]; int n; };
  std::vector<WireEntry> wire_list;
  std::vector<BeamPair> beam_list;
  std::vector<WireNet::BeamSection<WireNet::Lanes>> section_list;  // [pair - ncircular]
  int nbeam;      // beam bonds in beam_list
  int ncircular;  // pairs of circular beams, at the front of beam_list
  long list_version;
  class FixWirenetBonds *history;

  std::vector<WireNet::BondTypeSpec> specs;                 // [type]
  std::vector<std::unique_ptr<WireNet::WireLaw>> wires;     // [type], null if not a wire or brake
  std::vector<std::unique_ptr<WireNet::BeamLaw>> beams;     // [type], null if not a beam
  int any_beam;
  int any_strength;      // a beam type with `strength`
  int any_beam_damping;  // a beam type with `damping` > 0
  int any_damping;       // any type with `damping` > 0
  // per bond type, in this compute() (energy budget): power dissipated by bond damping, elastic
  // energy (with eflag)
  std::vector<double> damping_power, elastic_energy;
  // per bond type: this rank's sum of the intact wire and brake bonds' plastic work when the
  // tally was last brought up to date (sync_plastic), and scratch for the sum now
  std::vector<double> plastic_seen, plastic_now;
  long computes, plastic_synced;  // compute() calls; the call the tally is up to date with
  void sum_plastic(std::vector<double> &per_type) const;

  void allocate();
  void set_type(int type, const WireNet::BondTypeSpec &spec);
  void build_list();
  void init_record(const Entry &e, double length);
  inline void compute_wire(const WireEntry &e, double dx, double dy, double dz, double r, int eflag, double **f);
  template <int EVFLAG, bool STRENGTH, bool SECTION> void compute_beams(int eflag, int q0, int q1);
  void pad_last_pair(WireNet::BeamSection<WireNet::Lanes> *s);
  void break_beam(BeamPair &p, int k);
  void damp_beams();
  void report_timestep();
  void ensure_history_fix();
  bool beam_bonds_present() const;  // any bond of a beam type on any rank (collective)
  void report_types();
  bool duplicates_checked;
  void check_duplicate_bonds();  // a bond listed twice in the data file (collective)
};

}

#endif
#endif
