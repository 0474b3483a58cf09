/* GENERATED FILE - DO NOT EDIT.
 * step_c004: one closed-loop step (plant + c004 + actuators), RK4 over dt: measure, control_c004, plant_advance
 * Produced by `python build.py` from family 'controller_c004' (hash 44ce3e428007c452734a34ae06d897325f257e3b845b6c868359d3a4f013ad5e),
 * derived from:
 *   symbolic/__init__.py
 *   symbolic/actuators.py
 *   symbolic/closed_loop.py
 *   symbolic/codegen/__init__.py
 *   symbolic/codegen/c_composition.py
 *   symbolic/codegen/codegen.py
 *   symbolic/codegen/functions.py
 *   symbolic/codegen/reciprocals.py
 *   symbolic/codegen/specialisation.py
 *   symbolic/codegen/structural_cse.py
 *   symbolic/codegen/to_casadi.py
 *   symbolic/constraints.py
 *   symbolic/controllers/__init__.py
 *   symbolic/controllers/c004.py
 *   symbolic/environment.py
 *   symbolic/faults.py
 *   symbolic/kepler.py
 *   symbolic/layout.py
 *   symbolic/mass_properties.py
 *   symbolic/orbit.py
 *   symbolic/plant.py
 *   symbolic/relative_attitude.py
 *   symbolic/relative_translation.py
 *   symbolic/rigid_body.py
 *   symbolic/rotations.py
 *   symbolic/special.py
 *   symbolic/target_orbit_state.py
 * Operations: 29159 (CasADi SX instructions).  Edit symbolic/ and rebuild instead.
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

int step_c004(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
int step_c004_work(casadi_int *sz_arg, casadi_int* sz_res, casadi_int *sz_iw, casadi_int *sz_w);
casadi_int step_c004_n_in(void);
casadi_int step_c004_n_out(void);
const casadi_int* step_c004_sparsity_in(casadi_int i);
const casadi_int* step_c004_sparsity_out(casadi_int i);

#ifdef __cplusplus
} /* extern "C" */
#endif
