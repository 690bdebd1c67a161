/* WireNet: fix wirenet/shackle, net nodes held on ropes by shackles that slide along the rope
   with Coulomb friction. See doc/fix_wirenet_shackle.md. */

#ifdef FIX_CLASS

FixStyle(wirenet/shackle,FixWirenetShackle)

#else

#ifndef LMP_FIX_WIRENET_SHACKLE_H
#define LMP_FIX_WIRENET_SHACKLE_H

#include "fix.h"

#include <memory>
#include <string>
#include <vector>

#include "wirenet_shackle_law.h"

namespace LAMMPS_NS {

class FixWirenetShackle : public Fix {
 public:
  FixWirenetShackle(class LAMMPS *, int, char **);
  ~FixWirenetShackle();
  int setmask();
  void init();
  void setup(int);
  void post_force(int);
  double compute_scalar();
  double compute_vector(int);

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
  int pack_reverse_comm(int, int, double *);
  void unpack_reverse_comm(int, int *, double *);
  void write_restart(FILE *);
  void restart(char *);
  double memory_usage();

 private:
  std::unique_ptr<WireNet::ShackleLaw> law;
  std::string path;
  struct Rope {
    std::string id;
    std::vector<int> tags;   // atom IDs along the rope
  };
  struct Shackle {
    int tag;                 // the shackle atom
    int rope;                // index into ropes
  };
  std::vector<Rope> ropes;
  std::vector<Shackle> shackles;

  // per atom (only shackle atoms use them): [0] segment index k (-1: not placed yet), [1] xi,
  // [2] 1 if it slid at the last step (what the setup pass reports)
  double **hist;
  // forces on ghost rope atoms, 3 per atom, zero outside post_force (reverse communication)
  std::vector<double> fghost;

  double work_mine[2];       // friction work, normal-damping work of this rank's shackles [J]
  double elastic_mine;       // this step: elastic energy of this rank's shackles [J]
  int sliding_mine;          // this step: this rank's shackles at the friction cap
  double fmax_mine;          // this step: largest |F| on this rank's shackles [N]
  double sums[5];            // reduced: work, damping work, elastic, sliding, largest |F|

  void read_file(const char *);
  void check_atoms_exist();
  void place_new_shackles();
  void shackle_forces(bool setup_pass);
  void reduce();
};

}

#endif
#endif
