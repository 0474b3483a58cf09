/* GENERATED FILE - DO NOT EDIT.
 * step_baseline: one closed-loop step (plant + baseline + actuators), RK4 over dt: measure, control_baseline, plant_advance
 * Produced by `python build.py` from family 'controller_baseline' (hash 2076317edf48540e1e1d7102dcce4265a11e6ef95e91d7062b978430bd85e3be),
 * derived from:
 *   symbolic/__init__.py
 *   symbolic/codegen/__init__.py
 *   symbolic/codegen/c_composition.py
 *   symbolic/codegen/codegen.py
 *   symbolic/codegen/functions.py
 *   symbolic/codegen/reciprocals.py
 *   symbolic/codegen/specialisation.py
 *   symbolic/codegen/structural_cse.py
 *   symbolic/codegen/to_casadi.py
 *   symbolic/controllers/__init__.py
 *   symbolic/controllers/baseline.py
 *   symbolic/physics/__init__.py
 *   symbolic/physics/actuators.py
 *   symbolic/physics/closed_loop.py
 *   symbolic/physics/constraints.py
 *   symbolic/physics/environment.py
 *   symbolic/physics/faults.py
 *   symbolic/physics/kepler.py
 *   symbolic/physics/layout.py
 *   symbolic/physics/mass_properties.py
 *   symbolic/physics/orbit.py
 *   symbolic/physics/plant.py
 *   symbolic/physics/relative_attitude.py
 *   symbolic/physics/relative_translation.py
 *   symbolic/physics/rigid_body.py
 *   symbolic/physics/rotations.py
 *   symbolic/physics/special.py
 *   symbolic/physics/target_orbit_state.py
 * Operations: 28311 (CasADi SX instructions).  Edit symbolic/ and rebuild instead.
 */
#ifdef __cplusplus
extern "C" {
#endif

#ifndef casadi_real
#define casadi_real double
#endif

#ifndef casadi_int
#define casadi_int long long int
#endif

#ifndef CASADI_SYMBOL_EXPORT
  #if defined(_WIN32) || defined(__WIN32__) || defined(__CYGWIN__)
    #if defined(STATIC_LINKED)
      #define CASADI_SYMBOL_EXPORT
    #else
      #define CASADI_SYMBOL_EXPORT __declspec(dllexport)
    #endif
  #elif defined(__GNUC__) && defined(GCC_HASCLASSVISIBILITY)
    #define CASADI_SYMBOL_EXPORT __attribute__ ((visibility ("default")))
  #else
    #define CASADI_SYMBOL_EXPORT
  #endif
#endif

int measure(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int measure_kepler(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int control_baseline(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int plant_advance(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int plant_advance_kepler_nodist(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int plant_advance_kepler(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);

static const casadi_int step_baseline_z0_0[1] = {19};  /* measure_kepler: these entries of p are 0 */
static const casadi_int step_baseline_n0[2] = {43, 13};  /* sizes of measure's results */
static const casadi_int step_baseline_z1_0[43] = {19, 23, 24, 25, 26, 27, 28, 29, 30, 31, 35, 36, 37, 38, 39, 40, 44, 45, 46, 47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 62, 63, 64, 65, 66, 67, 71, 72, 73, 74, 75, 76};  /* plant_advance_kepler_nodist: these entries of p are 0 */
static const casadi_int step_baseline_z1_1[1] = {19};  /* plant_advance_kepler: these entries of p are 0 */
static const casadi_int step_baseline_n1[2] = {79, 83};  /* sizes of plant_advance's results */

/* 1 when the n entries idx of x are all 0 (a specialised callee applies) */
static int step_baseline_all_zero(const casadi_real* x, const casadi_int* idx, casadi_int n) {
  casadi_int i;
  for (i = 0; i < n; ++i) if (x[idx[i]] != 0) return 0;
  return 1;
}

static const casadi_int step_baseline_s0[3] = {92, 1, 1};
static const casadi_int step_baseline_s1[3] = {1, 1, 1};
static const casadi_int step_baseline_s2[3] = {376, 1, 1};
static const casadi_int step_baseline_s3[3] = {10, 1, 1};
static const casadi_int step_baseline_s4[3] = {18, 1, 1};
static const casadi_int step_baseline_s5[3] = {92, 1, 1};
static const casadi_int step_baseline_s6[3] = {136, 1, 1};

CASADI_SYMBOL_EXPORT int step_baseline_casadi_int_size(void) { return (int) sizeof(casadi_int); }
CASADI_SYMBOL_EXPORT int step_baseline_casadi_real_size(void) { return (int) sizeof(casadi_real); }

/* w: [meas (43), hold_next (13), cmd (9), xc_next (0), diag (1), zp_next (79), y_plant (83)] then the callees' work space */
CASADI_SYMBOL_EXPORT int step_baseline(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem) {
  (void) mem;
  const casadi_real* a[5];
  casadi_real* r[3];
  casadi_int i;
  if (!arg[0]) return 1;  /* z */
  if (!arg[1]) return 1;  /* t */
  if (!arg[2]) return 1;  /* p */
  if (!arg[3]) return 1;  /* k */
  if (!arg[4]) return 1;  /* w */
  /* (meas, hold_next) = measure(z, z+79, t, p, w) */
  a[0] = arg[0];
  a[1] = arg[0] + 79;
  a[2] = arg[1];
  a[3] = arg[2];
  a[4] = arg[4];
  r[0] = w + 0;
  r[1] = w + 43;
  /* or the first specialised copy whose entries step_baseline_z0_<j> of p are all 0 */
  if (step_baseline_all_zero(arg[2], step_baseline_z0_0, 1)) {
    if (measure_kepler(a, r, iw, w + 228, 0)) return 1;
  } else {
    if (measure(a, r, iw, w + 228, 0)) return 1;
  }
  /* (cmd, xc_next, diag) = control_baseline(meas, z+92, t, p, k) */
  a[0] = w + 0;
  a[1] = arg[0] + 92;
  a[2] = arg[1];
  a[3] = arg[2];
  a[4] = arg[3];
  r[0] = w + 56;
  r[1] = w + 65;
  r[2] = w + 65;
  if (control_baseline(a, r, iw, w + 228, 0)) return 1;
  /* (zp_next, y_plant) = plant_advance(z, t, p, w, cmd) */
  a[0] = arg[0];
  a[1] = arg[1];
  a[2] = arg[2];
  a[3] = arg[4];
  a[4] = w + 56;
  r[0] = w + 66;
  r[1] = w + 145;
  /* or the first specialised copy whose entries step_baseline_z1_<j> of p are all 0 */
  if (step_baseline_all_zero(arg[2], step_baseline_z1_0, 43)) {
    if (plant_advance_kepler_nodist(a, r, iw, w + 228, 0)) return 1;
  } else if (step_baseline_all_zero(arg[2], step_baseline_z1_1, 1)) {
    if (plant_advance_kepler(a, r, iw, w + 228, 0)) return 1;
  } else {
    if (plant_advance(a, r, iw, w + 228, 0)) return 1;
  }
  /* z_next = [zp_next, hold_next, xc_next] */
  if (res[0]) {
    for (i = 0; i < 79; ++i) res[0][0 + i] = w[66 + i];
    for (i = 0; i < 13; ++i) res[0][79 + i] = w[43 + i];
  }
  /* y = [meas, cmd, y_plant, diag] */
  if (res[1]) {
    for (i = 0; i < 43; ++i) res[1][0 + i] = w[0 + i];
    for (i = 0; i < 9; ++i) res[1][43 + i] = w[56 + i];
    for (i = 0; i < 83; ++i) res[1][52 + i] = w[145 + i];
    for (i = 0; i < 1; ++i) res[1][135 + i] = w[65 + i];
  }
  return 0;
}

CASADI_SYMBOL_EXPORT int step_baseline_alloc_mem(void) { return 0; }
CASADI_SYMBOL_EXPORT int step_baseline_init_mem(int mem) { (void) mem; return 0; }
CASADI_SYMBOL_EXPORT void step_baseline_free_mem(int mem) { (void) mem; }
CASADI_SYMBOL_EXPORT int step_baseline_checkout(void) { return 0; }
CASADI_SYMBOL_EXPORT void step_baseline_release(int mem) { (void) mem; }
CASADI_SYMBOL_EXPORT void step_baseline_incref(void) {}
CASADI_SYMBOL_EXPORT void step_baseline_decref(void) {}
CASADI_SYMBOL_EXPORT casadi_int step_baseline_n_in(void) { return 5; }
CASADI_SYMBOL_EXPORT casadi_int step_baseline_n_out(void) { return 2; }
CASADI_SYMBOL_EXPORT casadi_real step_baseline_default_in(casadi_int i) { (void) i; return 0; }

CASADI_SYMBOL_EXPORT const char* step_baseline_name_in(casadi_int i) {
  switch (i) {
    case 0: return "z";
    case 1: return "t";
    case 2: return "p";
    case 3: return "k";
    case 4: return "w";
    default: return 0;
  }
}

CASADI_SYMBOL_EXPORT const char* step_baseline_name_out(casadi_int i) {
  switch (i) {
    case 0: return "z_next";
    case 1: return "y";
    default: return 0;
  }
}

CASADI_SYMBOL_EXPORT const casadi_int* step_baseline_sparsity_in(casadi_int i) {
  switch (i) {
    case 0: return step_baseline_s0;
    case 1: return step_baseline_s1;
    case 2: return step_baseline_s2;
    case 3: return step_baseline_s3;
    case 4: return step_baseline_s4;
    default: return 0;
  }
}

CASADI_SYMBOL_EXPORT const casadi_int* step_baseline_sparsity_out(casadi_int i) {
  switch (i) {
    case 0: return step_baseline_s5;
    case 1: return step_baseline_s6;
    default: return 0;
  }
}

CASADI_SYMBOL_EXPORT int step_baseline_work(casadi_int *sz_arg, casadi_int* sz_res, casadi_int *sz_iw, casadi_int *sz_w) {
  if (sz_arg) *sz_arg = 5;
  if (sz_res) *sz_res = 2;
  if (sz_iw) *sz_iw = 0;
  if (sz_w) *sz_w = 1405;
  return 0;
}

CASADI_SYMBOL_EXPORT int step_baseline_work_bytes(casadi_int *sz_arg, casadi_int* sz_res, casadi_int *sz_iw,
                                          casadi_int *sz_w) {
  if (sz_arg) *sz_arg = 5*sizeof(const casadi_real*);
  if (sz_res) *sz_res = 2*sizeof(casadi_real*);
  if (sz_iw) *sz_iw = 0*sizeof(casadi_int);
  if (sz_w) *sz_w = 1405*sizeof(casadi_real);
  return 0;
}

#ifdef __cplusplus
} /* extern "C" */
#endif
