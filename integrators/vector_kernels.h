// The state-vector operations ARKODE calls on every step, compiled with the project's flags.
//
// Debian 12's SUNDIALS 6.4.1 is built without optimisation: its serial N_Vector kernels (in both
// libsundials_nvecserial and the copy inside libsundials_arkode) load and store every loop index
// through the stack, 13 instructions per element for a copy. Measured on the 1,000-disc pile,
// ARKODE's vector work per erk2 step cost 1.6 force evaluations. SUNDIALS lets a user replace a
// vector's operations (the N_Vector ops table, which clones inherit); these are plain loops with
// the same arithmetic in the same order as SUNDIALS' own, so results do not change.
#pragma once
#include <sundials/sundials_nvector.h>

namespace kiln {

// Installs the kernels in v's operations table (clones made afterwards inherit them).
void use_vector_kernels(N_Vector v);

}  // namespace kiln
