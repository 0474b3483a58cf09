"""An exported package compiled for this machine and called step by step (ctypes): the host side of the
lockstep runs (``rpo pil --on host``) and the single-precision error measurement.

The package's own C files are compiled unchanged, with the package's numerical flags
(``-O2 -ffp-contract=off``), beside a small shim that converts between the simulation's doubles and
the package's real type and owns nothing (the structs live in buffers this module allocates).  The
library is cached under a sha256 of every input (sources, shim, compiler identity, flags), sealed
and built atomically (:func:`rpo.runtime.model.cache.ensure_built`), so it is never loaded stale.
"""

from __future__ import annotations

import ctypes
import hashlib
import json
from pathlib import Path

import numpy as np

from rpo.runtime.errors import ModelError
from rpo.runtime.flight.tools import NUMERIC_FLAGS
from rpo.runtime.model.cache import cache_dir, ensure_built
from rpo.runtime.model.toolchain import compiler_command, run_cc

_SHIM = """/* rpo host shim (not flight code): the package's structs in caller-given buffers, doubles at the edge */
#include <stddef.h>
#include "@P@.h"
#include "@P@_io.h"
#define NP (@U@_N_PARAMS + 1)
#define NI (@U@_N_INPUTS + 1)
#define NO (@U@_N_OUTPUTS + 1)
#define NS (@U@_N_STATE + 1)
size_t shim_params_size(void) { return sizeof(@P@_params_t); }
size_t shim_state_size(void) { return sizeof(@P@_state_t); }
static void state_out(const @P@_state_t *s, double *out)
{
    @P@_real_t a[NS];
    int i;
    @P@_state_to_array(s, a);
    for (i = 0; i < @U@_N_STATE; ++i) { out[i] = (double)a[i]; }
}
void shim_init(void *pp, void *sp, const double *params, const double *start, double *state)
{
    @P@_real_t a[NP], b[NI];
    @P@_inputs_t in;
    int i;
    for (i = 0; i < @U@_N_PARAMS; ++i) { a[i] = (@P@_real_t)params[i]; }
    @P@_params_from_array((@P@_params_t *)pp, a);
    @P@_initialize((@P@_state_t *)sp, (const @P@_params_t *)pp);
    if (start != NULL) {
        for (i = 0; i < @U@_N_INPUTS; ++i) { b[i] = (@P@_real_t)start[i]; }
        @P@_inputs_from_array(&in, b);
@START@
    }
    (void)in; (void)b;
    state_out((const @P@_state_t *)sp, state);
}
void shim_set_state(void *sp, const double *state)
{
    @P@_real_t a[NS];
    int i;
    for (i = 0; i < @U@_N_STATE; ++i) { a[i] = (@P@_real_t)state[i]; }
    @P@_state_from_array((@P@_state_t *)sp, a);
}
void shim_step(void *pp, void *sp, const double *inputs, double *outputs, double *state)
{
    @P@_real_t b[NI], o[NO];
    @P@_inputs_t in;
    @P@_outputs_t out;
    int i;
    for (i = 0; i < @U@_N_INPUTS; ++i) { b[i] = (@P@_real_t)inputs[i]; }
    @P@_inputs_from_array(&in, b);
    @P@_step((@P@_state_t *)sp, (const @P@_params_t *)pp, &in, &out);
    @P@_outputs_to_array(&out, o);
    for (i = 0; i < @U@_N_OUTPUTS; ++i) { outputs[i] = (double)o[i]; }
    state_out((const @P@_state_t *)sp, state);
}
"""

_D = ctypes.POINTER(ctypes.c_double)


def package_info(folder: Path) -> dict:
    """The package's ``<prefix>.json`` (its interface as data)."""
    found = [p for p in Path(folder).glob("rpo_*.json")]
    if len(found) != 1:
        raise ModelError(f"{folder} is not an rpo export (no single rpo_<name>.json in it): run `rpo export` first")
    try:
        return json.loads(found[0].read_text())
    except (OSError, ValueError) as exc:
        raise ModelError(f"{found[0]} cannot be read: {exc}") from None


def flight_sources(folder: Path) -> list[Path]:
    """The package's flight C files (every ``*.c`` but the host test programs ``test_*.c``)."""
    return sorted(p for p in Path(folder).glob("*.c") if not p.name.startswith("test_"))


class HostController:
    """The package in ``folder`` compiled for this machine: :meth:`init`, then :meth:`step` per sample."""

    def __init__(self, folder: Path, log=None) -> None:
        self.folder = Path(folder)
        self.info = package_info(self.folder)
        prefix = self.info["prefix"]
        sizes = self.info["sizes"]
        self.n_params, self.n_inputs = int(sizes["params"]), int(sizes["inputs"])
        self.n_outputs, self.n_state = int(sizes["outputs"]), int(sizes["state"])
        shim = (_SHIM.replace("@START@", f"        {prefix}_start((@P@_state_t *)sp, (const @P@_params_t *)pp, &in);"
                              if self.info.get("start_function") else "")
                .replace("@P@", prefix).replace("@U@", prefix.upper()))
        cc, cc_id = compiler_command()
        sources = flight_sources(self.folder)
        headers = sorted(self.folder.glob("*.h"))
        h = hashlib.sha256(json.dumps({"cc": cc_id, "flags": list(NUMERIC_FLAGS), "shim": shim}).encode())
        for f in sources + headers:
            h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
        lib = cache_dir() / "flight" / f"{prefix}-host-{h.hexdigest()[:24]}.so"
        lib.parent.mkdir(parents=True, exist_ok=True)
        srcs = [str(s) for s in sources]

        def build(tmp: Path) -> None:
            shim_c = tmp.with_suffix(".shim.c")
            shim_c.write_text(shim)
            try:
                run_cc([*cc, "-std=c99", *NUMERIC_FLAGS, "-fPIC", "-shared", "-I", str(self.folder), *srcs,
                        str(shim_c), "-o", str(tmp), "-lm"], f"compiling the export {prefix} for this machine", cc)
            finally:
                shim_c.unlink(missing_ok=True)

        ensure_built(lib, build, f"the host build of {prefix}", log=log)
        self._lib = ctypes.CDLL(str(lib))
        self._lib.shim_params_size.restype = ctypes.c_size_t
        self._lib.shim_state_size.restype = ctypes.c_size_t
        self._params = ctypes.create_string_buffer(int(self._lib.shim_params_size()))
        self._state = ctypes.create_string_buffer(int(self._lib.shim_state_size()))
        self._out = np.zeros(max(self.n_outputs, 1))
        self._st = np.zeros(max(self.n_state, 1))

    def _check(self, a: np.ndarray, n: int, what: str) -> np.ndarray:
        a = np.ascontiguousarray(a, dtype=float).ravel()
        if a.size != n:
            raise ModelError(f"{self.info['prefix']}: {what} needs {n} values, got {a.size}")
        return np.append(a, 0.0)  # never a zero-size buffer

    def init(self, params: np.ndarray, start: np.ndarray | None = None) -> np.ndarray:
        """Load ``params`` (flat), initialize (and start from ``start`` when the design has a start);
        return the states (flat)."""
        p = self._check(params, self.n_params, "params")
        s = self._check(start, self.n_inputs, "the start inputs") if start is not None else None
        self._lib.shim_init(self._params, self._state, p.ctypes.data_as(_D),
                            s.ctypes.data_as(_D) if s is not None else None, self._st.ctypes.data_as(_D))
        return self._st[:self.n_state].copy()

    def set_state(self, state: np.ndarray) -> None:
        """Overwrite the controller's states (flat; the step counter is kept)."""
        s = self._check(state, self.n_state, "the state")
        self._lib.shim_set_state(self._state, s.ctypes.data_as(_D))

    def step(self, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One step: (outputs, states after), flat."""
        x = self._check(inputs, self.n_inputs, "inputs")
        self._lib.shim_step(self._params, self._state, x.ctypes.data_as(_D), self._out.ctypes.data_as(_D),
                            self._st.ctypes.data_as(_D))
        return self._out[:self.n_outputs].copy(), self._st[:self.n_state].copy()

    def close(self) -> None:
        pass

    def __enter__(self) -> HostController:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
