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

int step_baseline(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int step_baseline_work(casadi_int *sz_arg, casadi_int* sz_res, casadi_int *sz_iw, casadi_int *sz_w);
casadi_int step_baseline_n_in(void);
casadi_int step_baseline_n_out(void);
const casadi_int* step_baseline_sparsity_in(casadi_int i);
const casadi_int* step_baseline_sparsity_out(casadi_int i);

#ifdef __cplusplus
} /* extern "C" */
#endif
