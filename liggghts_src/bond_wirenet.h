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
  // Tally the energy the bond dampers took over this step: called by fix wirenet/bonds at the
  // end of the step, with every node's (ghosts' too) full-step velocity current.
  void tally_damping();
  // fix_modify wirenet_bonds scale: every wire and brake bond's state (largest elongation and
  // its force) times ratio, the new scale over the old (this rank's bonds; between runs)
  void rescale_wire_states(double ratio);

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
  bool keep_damp_loads;  // this compute() keeps its damping loads for the tally (fix_modify)
  // per bond type, in this compute() (energy budget): elastic energy (with eflag); at the end of
  // the step: power dissipated by bond damping
  std::vector<double> damping_power, elastic_energy;
  // The damping loads applied in this compute(), evaluated with the half-step velocities the
  // forces see, and tallied at the end of the step with the full-step ones: in velocity Verlet a
  // force F applied at step n changes the kinetic energy by exactly F.v(n) dt, so the dampers'
  // share of the budget is exact; the half-step power is off by F.a dt/2 per step, an O(dt) drift
  // that grows with the accelerations (a broken rope whipping).
  struct WireDampLoad { int e; double fr; };  // wire_list index; damping force / length
  struct BeamDampLoad { int i, j, type; double f[3], ti[3], tj[3]; };  // f on i, -f on j
  std::vector<WireDampLoad> wire_damp;
  std::vector<BeamDampLoad> beam_damp;
  std::vector<double> damping_pending;  // [type]: the second half of the last step's damper work
  // per bond type: this rank's sum of the intact wire and brake bonds' plastic work when the
  // tally was last brought up to date (sync_plastic), and scratch for the sum now
  std::vector<double> plastic_seen, plastic_now;
  long computes, plastic_synced;  // compute() calls; the call the tally is up to date with
  double law_scale, inv_scale2;   // the history fix's law_scale() when the list was built; 1 / its square
  void sum_plastic(std::vector<double> &per_type) const;

  void allocate();
  void set_type(int type, const WireNet::BondTypeSpec &spec);
  void build_list();
  void init_record(const Entry &e, double length);
  template <bool DAMPED> inline void compute_wire(int index, const WireEntry &e, double dx, double dy, double dz, double r, int eflag, double **f);
  template <bool DAMPED> void compute_wires(int eflag, double **x, double **f);
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
