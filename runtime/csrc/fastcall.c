/* rpo fast calls: a CPython extension type that calls one generated function with no per-call
 * conversions.
 *
 * Hand-written (not generated).  Built by rpo.runtime.fastcall into the cache when Python's
 * headers are present (else the ctypes path is used, same results, slower calls).
 *
 * A Caller holds the function pointer and its work space.  Each positional argument is a float
 * (size-1 inputs) or an object exporting a C-contiguous buffer of float64 with exactly the
 * input's number of elements: the function reads it in place.  The buffer of the last object
 * seen in each slot stays acquired, so the same array passed again costs one pointer comparison
 * (and cannot be resized while rpo holds it).  `out=` (one array, or a tuple with one per output)
 * is written in place the same way: a matrix output needs Fortran order, CasADi's layout.
 * An out= array overlapping an input goes to the fallback too (it copies the inputs first).
 * Anything else (wrong count, dtype, size, order) goes to the Python fallback `slow`, which
 * converts what it can and raises the error that names the argument and the shape wanted.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef int (*casadi_fn)(const double** arg, double** res, long long* iw, double* w, int mem);

typedef struct {
    PyObject_HEAD
    vectorcallfunc vectorcall;
    casadi_fn fn;
    int n_in, n_out;
    Py_ssize_t* in_size;
    Py_ssize_t* out_size;
    int* out_matrix;              /* 1: a matrix output (Fortran order needed for a 2-D out) */
    const double** arg;
    double** res;
    double* scalar;               /* one slot per input, for float arguments */
    PyObject** in_obj;            /* the cached object per input slot (NULL: none) */
    Py_buffer* in_view;
    PyObject** out_obj;
    Py_buffer* out_view;
    long long* iw;
    double* w;
    PyObject* slow;               /* slow(args, out): the Python fallback */
    PyObject* finish;             /* finish(): the result when no out= is given */
    double** own_out;             /* the default output buffers (from `defaults`) */
    PyObject* defaults;           /* keeps them alive */
} Caller;

static void release_slot(PyObject** obj, Py_buffer* view)
{
    if (*obj) {
        PyBuffer_Release(view);
        Py_CLEAR(*obj);
    }
}

/* Make `o` the cached object of a slot; 0 on success, -1 when it does not fit (no error set). */
static int acquire(PyObject* o, PyObject** obj, Py_buffer* view, Py_ssize_t size, int writable, int matrix)
{
    Py_buffer v;
    int flags = PyBUF_FORMAT | PyBUF_STRIDES | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(o, &v, flags) != 0) {
        PyErr_Clear();
        return -1;
    }
    int ok = v.itemsize == 8 && v.format && (strcmp(v.format, "d") == 0 || strcmp(v.format, "<d") == 0 ||
                                              strcmp(v.format, "=d") == 0)
             && v.len == size * 8;
    if (ok) {
        /* vectors: C-contiguous; a 2-D output of a matrix: Fortran-contiguous */
        if (matrix && v.ndim == 2)
            ok = PyBuffer_IsContiguous(&v, 'F');
        else
            ok = PyBuffer_IsContiguous(&v, 'C');
    }
    if (!ok) {
        PyBuffer_Release(&v);
        return -1;
    }
    release_slot(obj, view);
    *view = v;
    Py_INCREF(o);
    *obj = o;
    return 0;
}

static PyObject* call_slow(Caller* self, PyObject* const* args, Py_ssize_t n, PyObject* out)
{
    PyObject* tup = PyTuple_New(n);
    if (!tup) return NULL;
    for (Py_ssize_t i = 0; i < n; ++i) {
        Py_INCREF(args[i]);
        PyTuple_SET_ITEM(tup, i, args[i]);
    }
    PyObject* r = PyObject_CallFunctionObjArgs(self->slow, tup, out ? out : Py_None, NULL);
    Py_DECREF(tup);
    return r;
}

static PyObject* caller_vectorcall(PyObject* op, PyObject* const* args, size_t nargsf, PyObject* kwnames)
{
    Caller* self = (Caller*)op;
    Py_ssize_t n = PyVectorcall_NARGS(nargsf);
    PyObject* out = NULL;
    if (kwnames) {
        Py_ssize_t nk = PyTuple_GET_SIZE(kwnames);
        for (Py_ssize_t j = 0; j < nk; ++j) {
            PyObject* key = PyTuple_GET_ITEM(kwnames, j);
            if (PyUnicode_CompareWithASCIIString(key, "out") != 0) {
                PyErr_Format(PyExc_TypeError, "unexpected keyword argument %R (only out= is taken)", key);
                return NULL;
            }
            out = args[n + j];
        }
        if (out == Py_None) out = NULL;
    }
    if (n != self->n_in) return call_slow(self, args, n, out);
    for (int i = 0; i < self->n_in; ++i) {
        PyObject* o = args[i];
        if (o == self->in_obj[i]) {
            self->arg[i] = (const double*)self->in_view[i].buf;
            continue;
        }
        if (self->in_size[i] == 1 && (PyFloat_Check(o) || PyLong_Check(o))) {
            double v = PyFloat_AsDouble(o);
            if (v == -1.0 && PyErr_Occurred()) return NULL;
            self->scalar[i] = v;
            self->arg[i] = &self->scalar[i];
            continue;
        }
        if (acquire(o, &self->in_obj[i], &self->in_view[i], self->in_size[i], 0, 0) != 0)
            return call_slow(self, args, n, out);
        self->arg[i] = (const double*)self->in_view[i].buf;
    }
    if (out) {
        if (self->n_out == 1 && !PyTuple_Check(out)) {
            if (out != self->out_obj[0] &&
                acquire(out, &self->out_obj[0], &self->out_view[0], self->out_size[0], 1, self->out_matrix[0]) != 0)
                return call_slow(self, args, n, out);
            self->res[0] = (double*)self->out_view[0].buf;
        } else {
            if (!PyTuple_Check(out) || PyTuple_GET_SIZE(out) != self->n_out) return call_slow(self, args, n, out);
            for (int j = 0; j < self->n_out; ++j) {
                PyObject* o = PyTuple_GET_ITEM(out, j);
                if (o != self->out_obj[j] &&
                    acquire(o, &self->out_obj[j], &self->out_view[j], self->out_size[j], 1, self->out_matrix[j]) != 0)
                    return call_slow(self, args, n, out);
                self->res[j] = (double*)self->out_view[j].buf;
            }
        }
        /* an output written over an input (out=x): the generated code reads inputs after it has
         * begun writing outputs, so such a call goes to the fallback, which copies the inputs */
        for (int j = 0; j < self->n_out; ++j) {
            const char* o0 = (const char*)self->res[j];
            const char* o1 = o0 + self->out_size[j] * 8;
            for (int i = 0; i < self->n_in; ++i) {
                const char* i0 = (const char*)self->arg[i];
                const char* i1 = i0 + self->in_size[i] * 8;
                if (o0 < i1 && i0 < o1) return call_slow(self, args, n, out);
            }
        }
    } else {
        for (int j = 0; j < self->n_out; ++j) self->res[j] = self->own_out[j];
    }
    if (self->fn(self->arg, self->res, self->iw, self->w, 0) != 0) {
        PyErr_SetString(PyExc_FloatingPointError, "the generated function reported an evaluation error");
        return NULL;
    }
    if (out) {
        Py_INCREF(out);
        return out;
    }
    return PyObject_CallNoArgs(self->finish);
}

static void caller_dealloc(PyObject* op)
{
    Caller* self = (Caller*)op;
    PyObject_GC_UnTrack(op);
    for (int i = 0; i < self->n_in; ++i)
        if (self->in_obj) release_slot(&self->in_obj[i], &self->in_view[i]);
    for (int j = 0; j < self->n_out; ++j)
        if (self->out_obj) release_slot(&self->out_obj[j], &self->out_view[j]);
    PyMem_Free(self->in_size); PyMem_Free(self->out_size); PyMem_Free(self->out_matrix);
    PyMem_Free(self->arg); PyMem_Free(self->res); PyMem_Free(self->scalar);
    PyMem_Free(self->in_obj); PyMem_Free(self->in_view); PyMem_Free(self->out_obj); PyMem_Free(self->out_view);
    PyMem_Free(self->own_out);
    Py_CLEAR(self->slow); Py_CLEAR(self->finish); Py_CLEAR(self->defaults);
    PyTypeObject* tp = Py_TYPE(op);
    tp->tp_free(op);
}

static int caller_traverse(PyObject* op, visitproc visit, void* arg)
{
    Caller* self = (Caller*)op;
    Py_VISIT(self->slow);
    Py_VISIT(self->finish);
    Py_VISIT(self->defaults);
    return 0;
}

static int caller_clear(PyObject* op)
{
    Caller* self = (Caller*)op;
    Py_CLEAR(self->slow);
    Py_CLEAR(self->finish);
    return 0;
}

/* Caller(fn_address, in_sizes, out_sizes, out_matrix, iw_address, w_address, defaults, slow, finish)
 * defaults: a tuple of writable float64 buffers, the default outputs (kept alive here). */
static int caller_init(PyObject* op, PyObject* a, PyObject* kw)
{
    Caller* self = (Caller*)op;
    unsigned long long fn, iw, w;
    PyObject *ins, *outs, *mats, *defaults, *slow, *finish;
    if (!PyArg_ParseTuple(a, "KOOOKKOOO", &fn, &ins, &outs, &mats, &iw, &w, &defaults, &slow, &finish)) return -1;
    if (self->fn) {
        PyErr_SetString(PyExc_TypeError, "Caller is initialised once");
        return -1;
    }
    Py_ssize_t ni = PySequence_Size(ins), no = PySequence_Size(outs);
    if (ni < 0 || no < 0 || PySequence_Size(mats) != no || PySequence_Size(defaults) != no) {
        PyErr_SetString(PyExc_TypeError, "Caller: inconsistent sizes");
        return -1;
    }
    self->fn = (casadi_fn)(uintptr_t)fn;
    self->n_in = (int)ni;
    self->n_out = (int)no;
    self->in_size = PyMem_Calloc(ni + 1, sizeof(Py_ssize_t));
    self->out_size = PyMem_Calloc(no + 1, sizeof(Py_ssize_t));
    self->out_matrix = PyMem_Calloc(no + 1, sizeof(int));
    self->arg = PyMem_Calloc(ni + 1, sizeof(double*));
    self->res = PyMem_Calloc(no + 1, sizeof(double*));
    self->scalar = PyMem_Calloc(ni + 1, sizeof(double));
    self->in_obj = PyMem_Calloc(ni + 1, sizeof(PyObject*));
    self->in_view = PyMem_Calloc(ni + 1, sizeof(Py_buffer));
    self->out_obj = PyMem_Calloc(no + 1, sizeof(PyObject*));
    self->out_view = PyMem_Calloc(no + 1, sizeof(Py_buffer));
    self->own_out = PyMem_Calloc(no + 1, sizeof(double*));
    if (!self->in_size || !self->out_size || !self->out_matrix || !self->arg || !self->res || !self->scalar ||
        !self->in_obj || !self->in_view || !self->out_obj || !self->out_view || !self->own_out) {
        PyErr_NoMemory();
        return -1;
    }
    for (Py_ssize_t i = 0; i < ni; ++i) {
        PyObject* v = PySequence_GetItem(ins, i);
        self->in_size[i] = v ? PyLong_AsSsize_t(v) : -1;
        Py_XDECREF(v);
    }
    for (Py_ssize_t j = 0; j < no; ++j) {
        PyObject* v = PySequence_GetItem(outs, j);
        self->out_size[j] = v ? PyLong_AsSsize_t(v) : -1;
        Py_XDECREF(v);
        v = PySequence_GetItem(mats, j);
        self->out_matrix[j] = v ? PyObject_IsTrue(v) : 0;
        Py_XDECREF(v);
        v = PySequence_GetItem(defaults, j);
        if (!v) return -1;
        Py_buffer view;
        if (PyObject_GetBuffer(v, &view, PyBUF_WRITABLE | PyBUF_ANY_CONTIGUOUS) != 0) {
            Py_DECREF(v);
            return -1;
        }
        if (view.len != self->out_size[j] * 8) {
            PyBuffer_Release(&view);
            Py_DECREF(v);
            PyErr_SetString(PyExc_ValueError, "Caller: a default output buffer has the wrong size");
            return -1;
        }
        self->own_out[j] = (double*)view.buf;  /* `defaults` keeps the objects alive */
        PyBuffer_Release(&view);
        Py_DECREF(v);
    }
    if (PyErr_Occurred()) return -1;
    self->iw = (long long*)(uintptr_t)iw;
    self->w = (double*)(uintptr_t)w;
    Py_INCREF(defaults); self->defaults = defaults;
    Py_INCREF(slow); self->slow = slow;
    Py_INCREF(finish); self->finish = finish;
    self->vectorcall = caller_vectorcall;
    return 0;
}

static PyObject* caller_new(PyTypeObject* type, PyObject* a, PyObject* kw)
{
    (void)a; (void)kw;
    Caller* self = (Caller*)type->tp_alloc(type, 0);
    return (PyObject*)self;
}

static PyObject* caller_call(PyObject* op, PyObject* a, PyObject* kw)
{
    Caller* self = (Caller*)op;
    if (!self->fn) {
        PyErr_SetString(PyExc_TypeError, "Caller is not initialised");
        return NULL;
    }
    return PyVectorcall_Call(op, a, kw);
}

static PyTypeObject CallerType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "_rpo_fastcall.Caller",
    .tp_basicsize = sizeof(Caller),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE | Py_TPFLAGS_HAVE_GC | Py_TPFLAGS_HAVE_VECTORCALL,
    .tp_doc = "A generated function called in place (see runtime/csrc/fastcall.c).",
    .tp_new = caller_new,
    .tp_init = caller_init,
    .tp_dealloc = caller_dealloc,
    .tp_traverse = caller_traverse,
    .tp_clear = caller_clear,
    .tp_call = caller_call,
    .tp_vectorcall_offset = offsetof(Caller, vectorcall),
};

/* Python < 3.12 does not give a Python subclass the vectorcall flag of its C base: give it, when
 * the subclass keeps the base's call (so the vectorcall pointer is the base's). */
static PyObject* enable_vectorcall(PyObject* mod, PyObject* cls)
{
    (void)mod;
    if (!PyType_Check(cls) || !PyType_IsSubtype((PyTypeObject*)cls, &CallerType)) {
        PyErr_SetString(PyExc_TypeError, "enable_vectorcall: not a Caller subclass");
        return NULL;
    }
    PyTypeObject* tp = (PyTypeObject*)cls;
    if (tp->tp_call == caller_call && tp->tp_vectorcall_offset == offsetof(Caller, vectorcall))
        tp->tp_flags |= Py_TPFLAGS_HAVE_VECTORCALL;
    return PyBool_FromLong((tp->tp_flags & Py_TPFLAGS_HAVE_VECTORCALL) != 0);
}

static PyMethodDef methods[] = {
    {"enable_vectorcall", enable_vectorcall, METH_O, "Let a Caller subclass use the vectorcall path."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_rpo_fastcall", NULL, -1, methods};

PyMODINIT_FUNC PyInit__rpo_fastcall(void)
{
    if (PyType_Ready(&CallerType) < 0) return NULL;
    PyObject* m = PyModule_Create(&module);
    if (!m) return NULL;
    Py_INCREF(&CallerType);
    if (PyModule_AddObject(m, "Caller", (PyObject*)&CallerType) < 0) {
        Py_DECREF(&CallerType);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
