/* WireNet: per-bond history and node orientations for bond_style wirenet.
   Created by the bond style itself (ID wirenet_bonds); see doc/fix_wirenet_bonds.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/bonds,FixWirenetBonds)

#else

#ifndef LMP_FIX_WIRENET_BONDS_H
#define LMP_FIX_WIRENET_BONDS_H

#include "fix.h"
#include <vector>

namespace LAMMPS_NS {

class FixWirenetBonds : public Fix {
 public:
  // doubles per bond slot (the largest law record: the beam's)
  static const int NHIST = 13;
  // slot 0 of every record is the initial length: 0 = not initialised yet, < 0 = broken
  static const int L0 = 0;

  FixWirenetBonds(class LAMMPS *, int, char **);
  ~FixWirenetBonds();
  int setmask();
  void init();
  void setup_pre_exchange();
  void pre_exchange();
  void setup_pre_neighbor();
  void pre_neighbor();
  void setup_pre_force(int);
  void pre_force(int);
  void end_of_step();
  void post_run();
  int modify_param(int, char **);
  double compute_scalar();
  double compute_vector(int);
  double compute_array(int, int);
  double extend_cut_ghost();

  void grow_arrays(int);
  void copy_arrays(int, int, int);
  int pack_exchange(int, double *);
  int unpack_exchange(int, double *);
  int pack_restart(int, double *);
  void unpack_restart(int, int);
  int size_restart(int);
  int maxsize_restart();
  int pack_comm(int, int *, double *, int, int *);
  void unpack_comm(int, int, double *);
  int pack_border(int, int *, double *);
  int unpack_border(int, int, double *);
  int pack_reverse_comm(int, int, double *);
  void unpack_reverse_comm(int, int *, double *);
  void write_restart(FILE *);
  void restart(char *);
  double memory_usage();

  // --- interface for bond_style wirenet ---
  double *record(int i, int m) { return hist[i] + m * NHIST; }
  const double *record(int i, int m) const { return hist[i] + m * NHIST; }
  // rotation matrix (row-major) of node i's orientation, local and ghost atoms, current step
  const double *rotation(int i) const { return rot[i]; }
  const double *rotations() const { return rot[0]; }  // all of them: 9 per atom, one block
  // bumped whenever local atom indices or bond slots may have changed
  long list_version() const { return version; }
  // beam[t] != 0 for the bond types of a beam law: their end nodes are the only ones whose
  // orientation is tracked (an empty list: no beam bond exists)
  void use_orientations(const std::vector<char> &beam) { beam_type = beam; orient_flag = !beam.empty(); }
  // the ghost atoms need their velocities and angular velocities before the forces (bond
  // damping); sent by this fix unless LIGGGHTS sends them ('communicate ... vel yes')
  void use_velocities(bool on) { vel_flag = on ? 1 : 0; }
  // The ghosts must reach the longest bond's partner: set from the longest bond now (at init),
  // then grown at a neighbour-list build whenever a bond got longer than allowed for.
  void set_bond_reach(double longest) { ghost_extent = longest * (1.0 + REACH_HEADROOM); }
  // flag the bond (i, slot m) as broken; it leaves the atom's bond list at the next exchange;
  // energy = the elastic energy the bond stored when it broke (released)
  void break_bond(int i, int m, const double *mid, double elongation, double energy = 0.0);
  // Energy tallies of this rank's bonds, per bond type (global array columns 2-4; the global
  // vector [2-4] holds their sums): elastic energy released at ruptures, plastic work of the wire
  // and brake bonds, energy dissipated by bond damping.
  enum Tally { RELEASED = 0, PLASTIC = 1, DAMPING = 2, NTALLY = 3 };
  void add_tally(int type, Tally k, double w) { tally_mine[(size_t)type * NTALLY + k] += w; }
  // the bond style applied damping loads in this step's forces: at the end of the step, once
  // the ghosts have their full-step velocities, it tallies what they dissipated
  void request_damping_tally(class BondWirenet *b) { damping_source = b; }
  // whether the bond dampers' work is tallied at all (fix_modify damping_tally yes|no): a
  // settling that no budget reads skips the tally; the damping forces are the same either way
  bool damping_tallied() const { return damping_tally; }
  // the scale of the wire and brake laws (fix_modify scale; 1: as defined): the bond style
  // prepares their envelopes at it, its bonds' states are kept at it
  double law_scale() const { return law_scale_; }
  // The elastic energy of this rank's bonds of each type (e[type], type 1..nbondtypes) at the
  // current step (global array column 1): set by the bond style whenever it tallies energies.
  void set_elastic_energy(const std::vector<double> &e);
  // Force and torque on the local atoms when the bond style starts its compute(), i.e. the pair
  // forces (fix wirenet/contactwork pair); taken only once someone asked for them.
  void request_pair_forces() { pair_wanted = true; }
  void take_pair_forces();
  const std::vector<double> &pair_forces() const { return pair_snap; }
  // longest bond now (collective), from every atom's position gathered once: ghosts may be
  // missing or out of date between runs
  double max_bond_length_global();

 private:
  int nslots;        // bond slots per atom (atom->bond_per_atom when created)
  double **hist;     // [nmax][nslots * NHIST]
  double **quat;     // [nmax][4] node orientation (w, x, y, z), space frame
  double **rot;      // [nmax][9] its rotation matrix, derived each step
  int orient_flag, vel_flag;
  std::vector<char> beam_type;    // [type]: a beam law
  std::vector<int> oriented;      // local beam ends and the ghost ends of local beams: the only orientations read
  std::vector<double> end_mark;   // [nlocal + nghost] scratch of find_beam_ends
  long version;
  // the bond length the ghosts reach (LIGGGHTS adds the skin: in one neighbour-list interval no
  // bond grows by more); headroom above the longest bond so that growing is rare
  static constexpr double REACH_HEADROOM = 0.05;
  double ghost_extent;
  bool reach_grown;  // ghost_extent raised at the last list build: Comm::setup() before the next
  bigint nbroken_total;  // all ranks, since the bonds were created (restarted)
  int nbroken_pending;   // flagged on this rank, not yet removed from the bond lists
  // this rank's tallies since the bonds were created (rank 0 also holds a restart's totals),
  // [type * NTALLY + Tally]; row 0 holds the totals of a restart file written before the tallies
  // were kept per type (counted in the sums, in no type's row)
  std::vector<double> tally_mine;
  std::vector<double> elastic_mine;  // [type]: elastic energy at step elastic_step
  bigint elastic_step;
  double tally_sum(int k) const;
  void sync_tallies();  // the plastic-work tally brought up to the bonds' state
  bool pair_wanted;
  class BondWirenet *damping_source;  // set for this step by request_damping_tally
  bool damping_tally;                 // fix_modify damping_tally (default yes)
  double law_scale_;                  // fix_modify scale (default 1)
  std::vector<double> pair_snap;  // [6 * nlocal]: f and torque

  int maxlocal;  // rows allocated in array_local (this rank's ruptures, for dump local)

  void reset_atom(int);
  void refresh_rotations();
  void advance_orientations();
  void refresh_ghosts(bool advance);
  void remove_broken_bonds(bool scan_all);
  double check_partners_present();  // returns the longest local bond
  void follow_bond_reach(double longest_local);
  void find_beam_ends();
};

}

#endif
#endif
