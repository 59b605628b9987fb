/* stickslip._runner: simulate's run of a validated setting, in C.
 *
 * The facade (core.py) validates a setting once and keeps it, with the library's handle of the
 * built setting, in a _Call; every later call with equal arguments only runs it. This module
 * does that without the interpreter. FastPath, which stands for core.simulate, binds a call's
 * arguments, finds the kept setting and runs it; everything else it passes on to the Python
 * function. execute runs a setting for both paths: it calls the library's run_prepared (the
 * Fortran routine of _wrap.f90, reached through the function pointer f2py publishes as
 * run_prepared._cpointer, so that the one copy of the library in _stickslip runs it), arms
 * the SIGINT handler for a long run on the main thread, and builds the Result. Validation,
 * warnings and the exceptions stay in core.py. What setup() and set_main_thread() keep is read
 * by the runs, never written; the only flag written is the main thread's stop flag. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>
#include <stdint.h>
#include <string.h>
#include <structmember.h>

/* run_prepared of _wrap.f90 as f2py calls it: every argument by reference, in the Fortran
 * order, the hidden sizes nrow and nev included. */
typedef void (*run_prepared_f)(const int64_t *handle, const int *nrow, double *t_out, const int *n,
                               double *y_out, const int *nst, double *stats, int *stop,
                               double *events, const int *nev, int *status, double *cpu, const int *nd,
                               double *drive_force);

static run_prepared_f run_prepared = NULL;
static PyTypeObject *result_type = NULL;  /* core.Result */
static PyObject *no_events = NULL;        /* core._NO_EVENTS: Result.events of a run without */
static PyObject *no_event_rows = NULL;    /* core._NO_EVENT_ROWS: the (4, 0) buffer, never written */
static PyObject *make_events = NULL;      /* core._events(raw, count) */
static PyObject *empty_tuple = NULL;
static Py_ssize_t n_counters = 0, i_written = 0, i_nevents = 0;

/* The slots of _Call (C_*) and of Result (R_*) this module reads and writes, by their member
 * descriptors (both classes have __slots__): PyMember_GetOne / PyMember_SetOne read and write a
 * slot without the attribute lookup. The types are checked exactly before any slot is used. */
enum {
    C_FAST, C_HANDLE, C_N, C_ROWS, C_EVENTS_ROOM, C_N_BLOCKS, C_N_STATES, C_GRID, C_SCENE, C_LAW,
    C_METHOD, C_T_END, C_STATE_LABELS, C_RESOLVED, C_USED, C_ARM, C_MODEL, C_N_DRIVES, N_CALL_SLOTS
};
static const char *const call_slot_names[N_CALL_SLOTS] = {
    "fast", "handle", "n", "rows", "events_room", "n_blocks", "n_states", "grid", "scene", "law",
    "method", "t_end", "state_labels", "resolved", "used", "arm", "model", "n_drives"
};
enum {
    R_SCENE, R_LAW, R_METHOD, R_T_END, R_STATE_LABELS, R_T, R_X, R_V, R_Z, R_EVENTS, R_PARAMS,
    R_STATS, R_RAW, R_DRIVE_FORCE, N_RESULT_SLOTS
};
static const char *const result_slot_names[N_RESULT_SLOTS] = {
    "scene", "law", "method", "t_end", "state_labels", "t", "x", "v", "z", "events", "_params",
    "_stats", "_raw", "_drive_force"
};
static PyTypeObject *call_type = NULL;    /* core._Call */
static PyMemberDef *call_slots[N_CALL_SLOTS], *result_slots[N_RESULT_SLOTS];

/* The member definitions of `type`'s slots `names` (0, or -1 with an error set). */
static int find_slots(PyTypeObject *type, const char *const *slot_names, int count, PyMemberDef **out) {
    for (int i = 0; i < count; i++) {
        PyObject *descr = PyDict_GetItemString(type->tp_dict, slot_names[i]);
        if (descr == NULL || !Py_IS_TYPE(descr, &PyMemberDescr_Type)) {
            PyErr_Format(PyExc_TypeError, "_runner.setup: %s has no slot %s", type->tp_name, slot_names[i]);
            return -1;
        }
        out[i] = ((PyMemberDescrObject *)descr)->d_member;
    }
    return 0;
}

/* Slot `which` of a _Call (a new reference; NULL with AttributeError when unset). */
static PyObject *call_get(PyObject *call, int which) {
    return PyMember_GetOne((const char *)call, call_slots[which]);
}

/* An integer slot of a _Call (-1 with an exception set when it is not one). */
static Py_ssize_t call_int(PyObject *call, int which) {
    PyObject *value = call_get(call, which);
    if (value == NULL) return -1;
    Py_ssize_t out = PyLong_AsSsize_t(value);
    Py_DECREF(value);
    return out;
}

/* Set slot `which` of a Result to `value`, which it steals (NULL: an error is set). */
static int result_set(PyObject *result, int which, PyObject *value) {
    if (value == NULL) return -1;
    int rc = PyMember_SetOne((char *)result, result_slots[which], value);
    Py_DECREF(value);
    return rc;
}

/* Copy slot `from_slot` of a _Call to slot `to_slot` of a Result. */
static int copy_slot(PyObject *result, int to_slot, PyObject *call, int from_slot) {
    return result_set(result, to_slot, call_get(call, from_slot));
}

/* A view of `base`'s float64 data (a new reference, NULL with an error set). */
static PyObject *view_of(PyObject *base, int nd, npy_intp *dims, npy_intp *strides, char *data) {
    PyArray_Descr *descr = PyArray_DescrFromType(NPY_DOUBLE);
    if (descr == NULL) return NULL;
    PyObject *view = PyArray_NewFromDescr(&PyArray_Type, descr, nd, dims, strides, data, NPY_ARRAY_WRITEABLE,
                                          NULL);
    if (view == NULL) return NULL;
    Py_INCREF(base);                               /* stolen, also on failure */
    if (PyArray_SetBaseObject((PyArrayObject *)view, base) < 0) {
        Py_DECREF(view);
        return NULL;
    }
    return view;
}

/* Rows lo..hi-1 of the Fortran-ordered state y (n, nrow): a view of shape (nrow,) for one row
 * (one == 1), else (hi - lo, nrow). */
static PyObject *rows_of(PyObject *y, npy_intp lo, npy_intp hi, int one) {
    PyArrayObject *a = (PyArrayObject *)y;
    npy_intp dims[2] = {hi - lo, PyArray_DIM(a, 1)}, strides[2] = {PyArray_STRIDE(a, 0), PyArray_STRIDE(a, 1)};
    return view_of(y, one ? 1 : 2, one ? dims + 1 : dims, one ? strides + 1 : strides,
                   PyArray_BYTES(a) + lo * strides[0]);
}

/* The main thread's stop flag (written by the main thread's runs only, and by the SIGINT
 * handler a long run arms), and the main thread (set_main_thread: at import, after a fork). */
static int main_stop = 0;
static unsigned long main_thread = 0;

/* The Result of one run of `call`'s setting, on `t`: None for the grid the _Call keeps (copied)
 * or room for every step (its rows), else a writeable grid of this call (filled in place).
 * The library looks at the stop flag as a run starts, then every 4096 steps; a run the _Call
 * marks long (arm) is told so (-1 on the main thread, where the library arms a SIGINT handler
 * that sets the flag: KeyboardInterrupt once the run returns; -2 elsewhere, where Python's own
 * SIGINT handling stays). The flag also tells the library which clock times the run. A model's
 * setting with drives (n_drives > 0) also returns each drive's force (Result.drive_force).
 * Returns the Result whatever the run's status (its _raw[2]); the output is cut to the rows
 * written when the run ended early or output every step. */
static PyObject *execute_call(PyObject *call, PyObject *t) {
    PyObject *t_out = NULL, *y = NULL, *stats = NULL, *events = NULL, *forces = NULL, *result = NULL;
    int local_stop = 0, *stop_ptr = &local_stop, on_main = 0;

    if (!Py_IS_TYPE(call, call_type)) {
        PyErr_SetString(PyExc_TypeError, "_runner.execute: call must be a _Call");
        return NULL;
    }
    Py_ssize_t handle_v = call_int(call, C_HANDLE), n_v = call_int(call, C_N);
    Py_ssize_t room = call_int(call, C_EVENTS_ROOM), rows_mode = call_int(call, C_ROWS);
    Py_ssize_t nb = call_int(call, C_N_BLOCKS), nz = call_int(call, C_N_STATES);
    Py_ssize_t arm = call_int(call, C_ARM), model = call_int(call, C_MODEL), nd = call_int(call, C_N_DRIVES);
    if (PyErr_Occurred()) return NULL;
    /* a scene's state: nb blocks of (x, v, nz law states), stored x..., v..., z...; a model's:
     * nb bodies' x, their v, then its contacts' law states (nz in all) */
    if (handle_v == 0 || n_v < 1 || n_v > INT_MAX || room < 0 || room > INT_MAX || nb < 1 || nz < 0 ||
        n_v != (model ? 2 * nb + nz : nb * (2 + nz)) || rows_mode < 0 || nd < 0 || nd > (model ? nb : 0)) {
        PyErr_SetString(PyExc_ValueError, "_runner.execute: not a prepared setting");
        return NULL;
    }

    npy_intp nrow;
    if (t == Py_None && rows_mode) {               /* every step: room for the rows */
        nrow = rows_mode;
        t_out = PyArray_ZEROS(1, &nrow, NPY_DOUBLE, 0);
    } else if (t == Py_None) {                     /* the kept grid, copied */
        PyObject *grid = call_get(call, C_GRID);
        if (grid == NULL) return NULL;
        if (!PyArray_Check(grid) || PyArray_TYPE((PyArrayObject *)grid) != NPY_DOUBLE ||
            PyArray_NDIM((PyArrayObject *)grid) != 1 || !PyArray_IS_C_CONTIGUOUS((PyArrayObject *)grid)) {
            Py_DECREF(grid);
            PyErr_SetString(PyExc_TypeError, "_runner.execute: the setting keeps no grid");
            return NULL;
        }
        nrow = PyArray_DIM((PyArrayObject *)grid, 0);
        t_out = PyArray_EMPTY(1, &nrow, NPY_DOUBLE, 0);
        if (t_out != NULL && nrow)
            memcpy(PyArray_DATA((PyArrayObject *)t_out), PyArray_DATA((PyArrayObject *)grid),
                   (size_t)nrow * sizeof(double));
        Py_DECREF(grid);
    } else if (PyArray_Check(t) && PyArray_TYPE((PyArrayObject *)t) == NPY_DOUBLE &&
               PyArray_NDIM((PyArrayObject *)t) == 1 && PyArray_IS_C_CONTIGUOUS((PyArrayObject *)t) &&
               PyArray_ISWRITEABLE((PyArrayObject *)t)) {
        nrow = PyArray_DIM((PyArrayObject *)t, 0);
        t_out = Py_NewRef(t);
    } else {
        PyErr_SetString(PyExc_TypeError, "_runner.execute: t must be None or a writeable contiguous float64 grid");
        return NULL;
    }
    if (t_out == NULL) return NULL;
    if (nrow < 1 || nrow > INT_MAX) {
        PyErr_SetString(PyExc_ValueError, "_runner.execute: the output must have 1 to 2**31 - 1 rows");
        goto fail;
    }
    if (arm) {
        on_main = PyThread_get_thread_ident() == main_thread;
        if (on_main) {
            main_stop = -1;                        /* arm the SIGINT handler */
            stop_ptr = &main_stop;
        } else {
            local_stop = -2;                       /* long, but Python's own SIGINT handling stays */
        }
    }

    npy_intp ydims[2] = {n_v, nrow}, sdims[1] = {n_counters}, edims[2] = {4, room}, fdims[2] = {nd, nrow};
    y = PyArray_EMPTY(2, ydims, NPY_DOUBLE, 1);   /* Fortran order; the library writes all of it */
    stats = PyArray_EMPTY(1, sdims, NPY_DOUBLE, 0);
    events = room ? PyArray_ZEROS(2, edims, NPY_DOUBLE, 1) : Py_NewRef(no_event_rows);
    /* a model's drives: each one's force at each row (Fortran order), written by the library */
    forces = nd ? PyArray_EMPTY(2, fdims, NPY_DOUBLE, 1) : Py_NewRef(Py_None);
    if (y == NULL || stats == NULL || events == NULL || forces == NULL) goto fail;

    int64_t handle = (int64_t)handle_v;
    int nrow_i = (int)nrow, n_i = (int)n_v, nst = (int)n_counters, nev = (int)room, nd_i = (int)nd, status = 0;
    double cpu = 0.0, no_force = 0.0;
    double *t_data = (double *)PyArray_DATA((PyArrayObject *)t_out);
    double *s_data = (double *)PyArray_DATA((PyArrayObject *)stats);
    double *y_data = (double *)PyArray_DATA((PyArrayObject *)y);
    double *e_data = (double *)PyArray_DATA((PyArrayObject *)events);
    double *f_data = nd ? (double *)PyArray_DATA((PyArrayObject *)forces) : &no_force;
    Py_BEGIN_ALLOW_THREADS
    run_prepared(&handle, &nrow_i, t_data, &n_i, y_data, &nst, s_data, stop_ptr, e_data, &nev, &status, &cpu,
                 &nd_i, f_data);
    Py_END_ALLOW_THREADS
    if (on_main && main_stop == 1) {               /* Ctrl-C during the run */
        PyErr_SetNone(PyExc_KeyboardInterrupt);
        goto fail;
    }

    npy_intp written = nrow;
    if (status != 0 || rows_mode) {                /* an early end, or every step: the rows written */
        written = (npy_intp)s_data[i_written];
        if (written < 0) written = 0;
        if (written > nrow) written = nrow;
        PyObject *t_cut = PyArray_EMPTY(1, &written, NPY_DOUBLE, 0);   /* a copy: an every-step
                                                                          buffer is not kept */
        if (t_cut == NULL) goto fail;
        if (written) memcpy(PyArray_DATA((PyArrayObject *)t_cut), t_data, (size_t)written * sizeof(double));
        Py_SETREF(t_out, t_cut);
        npy_intp cut[2] = {n_v, written};
        PyObject *y_cut = view_of(y, 2, cut, PyArray_STRIDES((PyArrayObject *)y), (char *)y_data);
        if (y_cut == NULL) goto fail;
        Py_SETREF(y, y_cut);
    }

    result = result_type->tp_new(result_type, empty_tuple, NULL);
    if (result == NULL) goto fail;
    if (copy_slot(result, R_SCENE, call, C_SCENE) || copy_slot(result, R_LAW, call, C_LAW) ||
        copy_slot(result, R_METHOD, call, C_METHOD) || copy_slot(result, R_T_END, call, C_T_END) ||
        copy_slot(result, R_STATE_LABELS, call, C_STATE_LABELS) || result_set(result, R_T, Py_NewRef(t_out)))
        goto fail;
    /* x, v, then the law's states (a row each, or all of them); on the chain a row per block;
     * a model's always (bodies or states, rows) */
    int one = !model && nb == 1;
    if (result_set(result, R_X, rows_of(y, 0, nb, one)) ||
        result_set(result, R_V, rows_of(y, nb, 2 * nb, one)) ||
        result_set(result, R_Z, rows_of(y, 2 * nb, n_v, one && nz == 1)))
        goto fail;
    /* drives: a (n_t, n_drives) view of the rows written; none: Result.drive_force makes its
     * (n_t, 0) array on first use */
    if (nd) {
        PyArrayObject *fa = (PyArrayObject *)forces;
        npy_intp tdims[2] = {written, nd}, tstrides[2] = {PyArray_STRIDE(fa, 1), PyArray_STRIDE(fa, 0)};
        if (result_set(result, R_DRIVE_FORCE, view_of(forces, 2, tdims, tstrides, PyArray_BYTES(fa))))
            goto fail;
    } else if (result_set(result, R_DRIVE_FORCE, Py_NewRef(Py_None))) {
        goto fail;
    }
    /* the counters and real counters in one vector; params and stats are built on first use */
    PyObject *raw = PyTuple_New(6);
    if (raw == NULL) goto fail;
    PyTuple_SET_ITEM(raw, 0, Py_NewRef(stats));
    PyTuple_SET_ITEM(raw, 1, Py_NewRef(Py_None));
    PyTuple_SET_ITEM(raw, 2, PyLong_FromLong(status));
    PyTuple_SET_ITEM(raw, 3, PyFloat_FromDouble(cpu));
    PyTuple_SET_ITEM(raw, 4, call_get(call, C_RESOLVED));
    PyTuple_SET_ITEM(raw, 5, call_get(call, C_USED));
    for (int i = 2; i < 6; i++) {
        if (PyTuple_GET_ITEM(raw, i) == NULL) {
            Py_DECREF(raw);
            goto fail;
        }
    }
    /* a scene's params are built from the resolved values on first use; a model has none */
    if (result_set(result, R_RAW, raw) || result_set(result, R_PARAMS, model ? PyDict_New() : Py_NewRef(Py_None)) ||
        result_set(result, R_STATS, Py_NewRef(Py_None)))
        goto fail;
    PyObject *ev = room ? PyObject_CallFunction(make_events, "On", events, (Py_ssize_t)s_data[i_nevents])
                        : Py_NewRef(no_events);
    if (result_set(result, R_EVENTS, ev)) goto fail;
    Py_DECREF(t_out); Py_DECREF(y); Py_DECREF(stats); Py_DECREF(events); Py_DECREF(forces);
    return result;

fail:
    Py_XDECREF(t_out); Py_XDECREF(y); Py_XDECREF(stats); Py_XDECREF(events); Py_XDECREF(forces);
    Py_XDECREF(result);
    return NULL;
}

static PyObject *execute(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "_runner.execute(call, t) takes 2 arguments");
        return NULL;
    }
    if (run_prepared == NULL) {
        PyErr_SetString(PyExc_RuntimeError, "_runner.setup has not run");
        return NULL;
    }
    return execute_call(args[0], args[1]);
}

/* set_main_thread(ident): the main thread (threading.main_thread().ident), whose long runs arm
 * the SIGINT handler. */
static PyObject *set_main_thread(PyObject *self, PyObject *ident) {
    (void)self;
    unsigned long value = PyLong_AsUnsignedLong(ident);
    if (value == (unsigned long)-1 && PyErr_Occurred()) return NULL;
    main_thread = value;
    Py_RETURN_NONE;
}

/* The key of a call's arguments in the facade's dict of settings (core._CALLS): the value of
 * each named parameter of simulate (given or its default), the type of each (so that True
 * never meets 1, valid where True is not), then each further keyword's name, value and type,
 * in the order given. A new reference, NULL with an error set. */
static PyObject *make_key(PyObject *const *named, Py_ssize_t n_named, PyObject *const *kw_names,
                          PyObject *const *kw_values, Py_ssize_t n_kw) {
    PyObject *key = PyTuple_New(2 * n_named + 3 * n_kw);
    if (key == NULL) return NULL;
    Py_ssize_t at = 0;
    for (Py_ssize_t i = 0; i < n_named; i++) PyTuple_SET_ITEM(key, at++, Py_NewRef(named[i]));
    for (Py_ssize_t i = 0; i < n_named; i++) PyTuple_SET_ITEM(key, at++, Py_NewRef((PyObject *)Py_TYPE(named[i])));
    for (Py_ssize_t i = 0; i < n_kw; i++) {
        PyTuple_SET_ITEM(key, at++, Py_NewRef(kw_names[i]));
        PyTuple_SET_ITEM(key, at++, Py_NewRef(kw_values[i]));
        PyTuple_SET_ITEM(key, at++, Py_NewRef((PyObject *)Py_TYPE(kw_values[i])));
    }
    return key;
}

/* The setting kept under `key` in `calls` (borrowed), NULL if none; with an error set only for
 * an error other than an unhashable argument, which sets *unhashable instead. */
static PyObject *find_call(PyObject *calls, PyObject *key, int *unhashable) {
    PyObject *call = PyDict_GetItemWithError(calls, key);
    *unhashable = 0;
    if (call == NULL && PyErr_Occurred() && PyErr_ExceptionMatches(PyExc_TypeError)) {
        PyErr_Clear();
        *unhashable = 1;
    }
    return call;
}

/* lookup(calls, kwargs, <the named arguments of simulate, in order>) -> (key, call): the key
 * of these arguments (None when one is unhashable: such a call is validated each time) and
 * the setting kept under it (None if none). */
static PyObject *lookup(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    (void)self;
    if (nargs < 3 || !PyDict_Check(args[0]) || !PyDict_Check(args[1])) {
        PyErr_SetString(PyExc_TypeError, "_runner.lookup(calls, kwargs, *named)");
        return NULL;
    }
    PyObject *kwargs = args[1];
    Py_ssize_t n_kw = PyDict_GET_SIZE(kwargs), pos = 0, i = 0;
    PyObject **kv = PyMem_Malloc(sizeof(PyObject *) * (size_t)(2 * n_kw + 1)), *k, *v;
    if (kv == NULL) return PyErr_NoMemory();
    while (PyDict_Next(kwargs, &pos, &k, &v) && i < n_kw) {
        kv[i] = k;
        kv[n_kw + i] = v;
        i++;
    }
    PyObject *key = make_key(args + 2, nargs - 2, kv, kv + n_kw, i);
    PyMem_Free(kv);
    if (key == NULL) return NULL;
    int unhashable;
    PyObject *call = find_call(args[0], key, &unhashable);
    if (call == NULL && PyErr_Occurred()) {
        Py_DECREF(key);
        return NULL;
    }
    PyObject *out = PyTuple_Pack(2, unhashable ? Py_None : key, call ? call : Py_None);
    Py_DECREF(key);
    return out;
}

/* FastPath(func, calls, failed): simulate as called. It binds the arguments as Python would
 * to func's parameters (its named ones, then further keywords), looks the setting up in
 * `calls` and, for a setting marked fast (no warnings to repeat, no SIGINT handler to arm, a
 * kept grid), runs it and returns its Result; failed(call, result) raises for a run that did
 * not reach t_end. Everything else (a new setting, a Model, bad arguments) is func's: the
 * call is passed on unchanged. functools.update_wrapper gives it func's name, docstring and
 * signature (__wrapped__). */
#define MAX_NAMED 16
#define MAX_KW 64
typedef struct {
    PyObject_HEAD
    vectorcallfunc vectorcall;
    PyObject *func, *calls, *failed, *dict;
    Py_ssize_t n_positional, n_named;
    PyObject *names[MAX_NAMED];           /* func's named parameters */
    PyObject *defaults[MAX_NAMED];        /* their defaults (NULL: required) */
} FastPath;

/* The index of parameter `name` among f's named ones, -1 if none (-2 with an error set). */
static Py_ssize_t param_index(FastPath *f, PyObject *name) {
    for (Py_ssize_t i = 0; i < f->n_named; i++)
        if (f->names[i] == name) return i;           /* interned names: the common case */
    if (PyUnicode_CheckExact(name) && PyUnicode_CHECK_INTERNED(name))
        return -1;                                   /* interned and none of them */
    for (Py_ssize_t i = 0; i < f->n_named; i++) {
        int eq = PyUnicode_Compare(f->names[i], name);
        if (eq == 0) return i;
        if (eq == -1 && PyErr_Occurred()) return -2;
    }
    return -1;
}

static PyObject *fast_vectorcall(PyObject *self, PyObject *const *args, size_t nargsf, PyObject *kwnames) {
    FastPath *f = (FastPath *)self;
    Py_ssize_t nargs = PyVectorcall_NARGS(nargsf), nkw = kwnames ? PyTuple_GET_SIZE(kwnames) : 0, n_extra = 0;
    PyObject *named[MAX_NAMED] = {NULL}, *extra_names[MAX_KW], *extra_values[MAX_KW];
    if (nargs > f->n_positional || nkw > MAX_KW) goto slow;
    for (Py_ssize_t i = 0; i < nargs; i++) named[i] = args[i];
    for (Py_ssize_t j = 0; j < nkw; j++) {
        PyObject *name = PyTuple_GET_ITEM(kwnames, j);
        Py_ssize_t i = param_index(f, name);
        if (i == -2) return NULL;
        if (i >= 0) {
            if (named[i] != NULL) goto slow;          /* given twice: func says so */
            named[i] = args[nargs + j];
        } else {
            extra_names[n_extra] = name;
            extra_values[n_extra++] = args[nargs + j];
        }
    }
    for (Py_ssize_t i = 0; i < f->n_named; i++) {
        if (named[i] == NULL) {
            if (f->defaults[i] == NULL) goto slow;    /* a required one missing: func says so */
            named[i] = f->defaults[i];
        }
    }
    if (!PyUnicode_CheckExact(named[0])) goto slow;   /* a Model: func runs it */
    PyObject *key = make_key(named, f->n_named, extra_names, extra_values, n_extra);
    if (key == NULL) return NULL;
    int unhashable;
    PyObject *call = find_call(f->calls, key, &unhashable);
    Py_DECREF(key);
    if (call == NULL) {
        if (PyErr_Occurred()) return NULL;
        goto slow;
    }
    if (!Py_IS_TYPE(call, call_type)) goto slow;
    Py_INCREF(call);                                  /* the dict may drop it during the run */
    PyObject *fast = call_get(call, C_FAST), *result = NULL, *out = NULL;
    int is_fast = fast ? PyObject_IsTrue(fast) : -1;
    Py_XDECREF(fast);
    if (is_fast <= 0) {
        Py_DECREF(call);
        if (is_fast < 0) return NULL;
        goto slow;
    }
    result = execute_call(call, Py_None);
    if (result != NULL) {
        PyObject *raw = PyMember_GetOne((const char *)result, result_slots[R_RAW]);
        long status = raw ? PyLong_AsLong(PyTuple_GET_ITEM(raw, 2)) : -1;
        Py_XDECREF(raw);
        if (raw != NULL && !(status == -1 && PyErr_Occurred()))
            out = status == 0 ? Py_NewRef(result) : PyObject_CallFunctionObjArgs(f->failed, call, result, NULL);
    }
    Py_XDECREF(result);
    Py_DECREF(call);
    return out;

slow:
    return PyObject_Vectorcall(f->func, args, nargsf, kwnames);
}

static PyObject *fast_new(PyTypeObject *type, PyObject *args, PyObject *kwds) {
    PyObject *func, *calls, *failed;
    if (kwds != NULL && PyDict_GET_SIZE(kwds)) {
        PyErr_SetString(PyExc_TypeError, "FastPath(func, calls, failed) takes no keywords");
        return NULL;
    }
    if (!PyArg_ParseTuple(args, "O!O!O", &PyFunction_Type, &func, &PyDict_Type, &calls, &failed))
        return NULL;
    PyCodeObject *code = (PyCodeObject *)PyFunction_GetCode(func);
    Py_ssize_t n_pos = code->co_argcount, n_named = n_pos + code->co_kwonlyargcount;
    if (!PyCallable_Check(failed) || n_named < 1 || n_named > MAX_NAMED || code->co_posonlyargcount ||
        (code->co_flags & CO_VARARGS) || !(code->co_flags & CO_VARKEYWORDS)) {
        PyErr_SetString(PyExc_ValueError, "FastPath: func must take named parameters and **kwargs only");
        return NULL;
    }
    FastPath *f = (FastPath *)type->tp_alloc(type, 0);
    if (f == NULL) return NULL;
    f->vectorcall = fast_vectorcall;
    f->func = Py_NewRef(func);
    f->calls = Py_NewRef(calls);
    f->failed = Py_NewRef(failed);
    f->n_positional = n_pos;
    f->n_named = n_named;
    PyObject *varnames = PyObject_GetAttrString((PyObject *)code, "co_varnames");
    PyObject *defaults = PyFunction_GetDefaults(func), *kwdefaults = PyFunction_GetKwDefaults(func);
    if (varnames == NULL) goto fail;
    Py_ssize_t n_def = defaults ? PyTuple_GET_SIZE(defaults) : 0;
    for (Py_ssize_t i = 0; i < n_named; i++) {
        PyObject *name = PyTuple_GET_ITEM(varnames, i);
        Py_INCREF(name);
        PyUnicode_InternInPlace(&name);
        f->names[i] = name;
        PyObject *d = NULL;
        if (i < n_pos) {
            if (i >= n_pos - n_def) d = PyTuple_GET_ITEM(defaults, i - (n_pos - n_def));
        } else if (kwdefaults != NULL) {
            d = PyDict_GetItemWithError(kwdefaults, name);
            if (d == NULL && PyErr_Occurred()) goto fail;
        }
        f->defaults[i] = d ? Py_NewRef(d) : NULL;
    }
    Py_DECREF(varnames);
    return (PyObject *)f;
fail:
    Py_XDECREF(varnames);
    Py_DECREF(f);
    return NULL;
}

static int fast_traverse(FastPath *f, visitproc visit, void *arg) {
    Py_VISIT(f->func);
    Py_VISIT(f->calls);
    Py_VISIT(f->failed);
    Py_VISIT(f->dict);
    for (Py_ssize_t i = 0; i < f->n_named; i++) Py_VISIT(f->defaults[i]);
    return 0;
}

static int fast_clear(FastPath *f) {
    Py_CLEAR(f->func);
    Py_CLEAR(f->calls);
    Py_CLEAR(f->failed);
    Py_CLEAR(f->dict);
    for (Py_ssize_t i = 0; i < f->n_named; i++) {
        Py_CLEAR(f->names[i]);
        Py_CLEAR(f->defaults[i]);
    }
    return 0;
}

static void fast_dealloc(FastPath *f) {
    PyObject_GC_UnTrack(f);
    fast_clear(f);
    Py_TYPE(f)->tp_free((PyObject *)f);
}

/* Pickled by name (as the function it stands for): its __module__ and __qualname__. */
static PyObject *fast_reduce(PyObject *self, PyObject *unused) {
    (void)unused;
    return PyObject_GetAttrString(self, "__qualname__");
}

static PyMethodDef fast_methods[] = {
    {"__reduce__", fast_reduce, METH_NOARGS, "Pickled by name."},
    {NULL, NULL, 0, NULL}
};

static PyGetSetDef fast_getset[] = {
    {"__dict__", PyObject_GenericGetDict, PyObject_GenericSetDict, NULL, NULL},
    {NULL, NULL, NULL, NULL, NULL}
};

static PyTypeObject FastPathType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "stickslip._runner.FastPath",
    .tp_basicsize = sizeof(FastPath),
    .tp_dealloc = (destructor)fast_dealloc,
    .tp_vectorcall_offset = offsetof(FastPath, vectorcall),
    .tp_call = PyVectorcall_Call,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC | Py_TPFLAGS_HAVE_VECTORCALL,
    .tp_doc = "simulate's fast path (see _runner.c).",
    .tp_traverse = (traverseproc)fast_traverse,
    .tp_clear = (inquiry)fast_clear,
    .tp_methods = fast_methods,
    .tp_getset = fast_getset,
    .tp_dictoffset = offsetof(FastPath, dict),
    .tp_new = fast_new,
};

/* setup(run_prepared_capsule, Result, _Call, no_events, no_event_rows, events, n_counters,
 *       i_written, i_nevents): what the runs need from _stickslip and core, once at import. */
static PyObject *setup(PyObject *self, PyObject *args) {
    (void)self;
    PyObject *capsule, *rtype, *ctype, *none_ev, *none_rows, *ev_fn;
    Py_ssize_t nc, iw, ine;
    if (!PyArg_ParseTuple(args, "OO!O!OO!Onnn", &capsule, &PyType_Type, &rtype, &PyType_Type, &ctype,
                          &none_ev, &PyArray_Type, &none_rows, &ev_fn, &nc, &iw, &ine))
        return NULL;
    void *fp = PyCapsule_GetPointer(capsule, PyCapsule_GetName(capsule));
    if (fp == NULL) return NULL;
    if (!PyCallable_Check(ev_fn) || nc < 1 || nc > INT_MAX || iw < 0 || iw >= nc || ine < 0 || ine >= nc ||
        PyArray_SIZE((PyArrayObject *)none_rows) != 0) {
        PyErr_SetString(PyExc_ValueError, "_runner.setup: bad arguments");
        return NULL;
    }
    if (find_slots((PyTypeObject *)ctype, call_slot_names, N_CALL_SLOTS, call_slots) ||
        find_slots((PyTypeObject *)rtype, result_slot_names, N_RESULT_SLOTS, result_slots))
        return NULL;
    run_prepared = (run_prepared_f)fp;
    Py_XSETREF(result_type, (PyTypeObject *)Py_NewRef(rtype));
    Py_XSETREF(call_type, (PyTypeObject *)Py_NewRef(ctype));
    Py_XSETREF(no_events, Py_NewRef(none_ev));
    Py_XSETREF(no_event_rows, Py_NewRef(none_rows));
    Py_XSETREF(make_events, Py_NewRef(ev_fn));
    n_counters = nc; i_written = iw; i_nevents = ine;
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"setup", setup, METH_VARARGS, "setup(run_prepared_capsule, Result, _Call, no_events, no_event_rows, "
     "events, n_counters, i_written, i_nevents): what the runs need, once at import."},
    {"execute", (PyCFunction)(void (*)(void))execute, METH_FASTCALL,
     "execute(call, t) -> Result: one run of a prepared setting (whatever its status)."},
    {"set_main_thread", set_main_thread, METH_O,
     "set_main_thread(ident): the thread whose long runs arm the SIGINT handler."},
    {"lookup", (PyCFunction)(void (*)(void))lookup, METH_FASTCALL,
     "lookup(calls, kwargs, *named) -> (key, call): the key of simulate's arguments and the setting kept under it."},
    {NULL, NULL, 0, NULL}
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_runner", "simulate's run of a validated setting, in C (see core.py).",
    -1, methods, NULL, NULL, NULL, NULL
};

PyMODINIT_FUNC PyInit__runner(void) {
    import_array();
    if (empty_tuple == NULL && (empty_tuple = PyTuple_New(0)) == NULL) return NULL;
    if (PyType_Ready(&FastPathType) < 0) return NULL;
    PyObject *m = PyModule_Create(&module);
    if (m == NULL) return NULL;
    if (PyModule_AddObjectRef(m, "FastPath", (PyObject *)&FastPathType) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
