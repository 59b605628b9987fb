/* stickslip.h: the C interface of the stickslip library (Fortran module stickslip_capi).
 *
 * Friction laws of Yoo & Lee (2008), the two scenes (box on a slope, spring-mass on a moving
 * belt), and the library's integrators (classical RK4, Dormand-Prince 5(4), RADAU5, implicit
 * Euler, generalized-alpha); RK4 and DOPRI5 also for a user's own ODE. Any law, scene and
 * method by code (ss_code) with parameters and controls by name: ss_run, ss_mu. A user's own
 * system of bodies, springs, dampers, forces and friction contacts: ss_model_* (at the end).
 * Units are SI: m, s, kg, m/s; angles in degrees.
 *
 * Every function except the *_default ones returns a status: SS_OK (0) on success, a
 * negative code otherwise (-1 .. -99: the run ended early; <= -100: one bad input).
 * ss_message() explains a code.
 *
 * Arrays: states are stored row by row, y_out[i * n + j] = component j at t_out[i]
 * (n = 2 for the scenes with a static law: x [m], v [m/s]; then the law's internal states).
 *
 * Link: cc prog.c $(pkg-config --cflags --libs stickslip)
 */
#ifndef STICKSLIP_H
#define STICKSLIP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The codes of laws, scenes, methods and status codes: SS_LAW_COULOMB, SS_SCENE_SLOPE,
 * SS_METHOD_RADAU5, SS_OK, SS_STEP_BUDGET, SS_BAD_MU_K, ... generated at build time from the
 * library's registry (every law, scene, method and parameter it has). */
#include "stickslip_codes.h"

/* Physical parameters; ss_params_default() gives the paper's Table 1 values. */
typedef struct {
    double mu_s;       /* static coefficient [-] (0.35) */
    double mu_k;       /* kinetic coefficient [-] (0.30) */
    double v_s;        /* static threshold velocity [m/s] (0.01) */
    double v_d;        /* dynamic threshold velocity, recurdyn law [m/s] (0.015) */
    double beta;       /* exponent of the proposed law [-] (1/3) */
    double a;          /* base of the proposed law, > 1 [-] (1.5) */
    double m;          /* mass, belt [kg] (10) */
    double g;          /* gravity [m/s^2] (9.81) */
    double theta_deg;  /* slope inclination [deg] (10) */
    double k;          /* spring stiffness, belt [N/m] (300) */
    double v_b;        /* belt speed [m/s] (1.5) */
} ss_params;

/* Integration controls of the explicit adaptive methods: ss_dopri5_options_default() gives
 * Hairer's DOPRI5 defaults, ss_dop853_options_default() his DOP853 ones (for ss_dop853). */
typedef struct {
    double hmin;          /* step floor; steps forced there when the error test fails (1e-6; 0: none) [s] */
    double hmax;          /* largest step (0: t_end - t0) [s] */
    double h0;            /* initial step (0: automatic) [s] */
    double safety;        /* 0.9 */
    double fac1;          /* smallest step ratio, 0.2 */
    double fac2;          /* largest step ratio, 10 */
    double beta;          /* PI stabilisation exponent, 0.04 */
    int64_t max_steps;    /* budget of attempted steps (default 10^8; RK4 uses it too) */
    int nstiff;           /* stiffness test every nstiff accepted steps (1000) */
    int allow_forced;     /* 1: take steps at hmin when the error test fails there (1) */
    int stop_on_stiff;    /* 1: stop with SS_STIFF when judged stiff (0) */
    int every_step;       /* 1: output every step into t_out/y_out instead of at t_out (0) */
} ss_dopri5_options;

/* Counters and outcome of one integration (names after Hairer's DOPRI5). */
typedef struct {
    int64_t nfev;      /* right-hand-side evaluations */
    int64_t nstep;     /* attempted steps */
    int64_t naccept;   /* accepted steps, forced ones included */
    int64_t nreject;   /* rejected steps after the first accepted one */
    int64_t nforced;   /* steps forced at hmin */
    int64_t nstiff;    /* stiffness tests that fired */
    int stiff;         /* 1: judged stiff */
    int n_written;     /* output rows written */
    double t_reached;  /* time reached [s] */
    double h_last;     /* last step size tried [s] */
    int status;        /* SS_OK or a negative code */
    int64_t njac;      /* Jacobian evaluations (implicit methods) */
    int64_t ndec;      /* LU decompositions (implicit methods) */
    int64_t nsol;      /* forward-backward substitutions (implicit methods) */
} ss_stats;

/* A user's right-hand side: dydt[0..n-1] = f(t, y[0..n-1]); data is passed through. */
typedef void (*ss_rhs)(double t, const double *y, double *dydt, int n, void *data);

void ss_params_default(ss_params *p);
void ss_dopri5_options_default(ss_dopri5_options *o);
void ss_dop853_options_default(ss_dopri5_options *o);

/* Copy the message of a status code into buf (at most buflen - 1 characters, NUL-terminated);
 * returns the message's full length. */
int ss_message(int status, char *buf, size_t buflen);

/* mu[i] = friction coefficient [-] of law at relative velocity v[i] [m/s], i < n.
 * Only the parameters the law uses are checked (v_d: recurdyn; beta, a: proposed). */
int ss_friction(int law, int64_t n, const double *v, double mu_s, double mu_k, double v_s,
                double v_d, double beta, double a, double *mu);

/* Simulate a scene with a law from (x0, v0) at t = 0 to t_end: RK4 with step h, or DOPRI5 with
 * rtol, atol and opts (NULL: defaults, for RK4 too: a budget of 10^8 steps). SS_METHOD_DOP853
 * reads opts but keeps its own safety, fac1, fac2 and beta (Hairer's 0.9, 0.333, 6, 0: the
 * struct's are DOPRI5's); ss_run sets them by name.
 * Laws with internal states need ss_run.
 * t_out[n_out]: requested output times in [0, t_end] (non-decreasing), or with
 * opts->every_step room for every step (overwritten with the step times).
 * y_out[2 * n_out]: (x, v) per row. stats may be NULL. */
int ss_simulate(int scene, int law, int method, const ss_params *p, double x0, double v0,
                double t_end, double h, double rtol, double atol, const ss_dopri5_options *opts,
                int n_out, double *t_out, double *y_out, ss_stats *stats);

/* Any law, scene and method of the registry, with parameters and controls by name.
 * Codes: ss_code("law" | "scene" | "method", name), 0 for an unknown name.
 * pkeys, ckeys: comma-separated names ("mu_s,v_s"; "" for none) valued by pvals[np], cvals[nc]
 * (flags and counts as doubles); the others take their defaults. y0[n] = (x0 [m], v0 [m/s], then the
 * law's internal states). rtol, atol: ntol = 1 or n values (adaptive methods).
 * t_out, y_out[n * n_out], stats: as for ss_simulate. */
int ss_code(const char *kind, const char *name);
int ss_run(int scene, int law, int method, const char *pkeys, int np, const double *pvals, int n,
           const double *y0, double t_end, int ntol, const double *rtol, const double *atol,
           const char *ckeys, int nc, const double *cvals, int n_out, double *t_out, double *y_out,
           ss_stats *stats);
/* mu[i] of law (a code) at v[i] [m/s], i < n, parameters by name as in ss_run. */
int ss_mu(int law, const char *pkeys, int np, const double *pvals, int64_t n, const double *v,
          double *mu);
/* The registry as text (one record per line, '|'-separated fields), copied as ss_message does. */
int ss_registry(char *buf, size_t buflen);

/* Integrate the user's y' = f(t, y) of dimension n from t0 to t_end with the library's
 * DOPRI5. rtol, atol: ntol = 1 (scalar) or n values. opts may be NULL (defaults).
 * t_out, y_out[n * n_out], stats: as for ss_simulate. */
int ss_dopri5(ss_rhs f, void *data, int n, double t0, const double *y0, double t_end, int ntol,
              const double *rtol, const double *atol, const ss_dopri5_options *opts, int n_out,
              double *t_out, double *y_out, ss_stats *stats);

/* The same with the library's DOP853 (Hairer's 8(5,3) pair, dense output of order 7). opts
 * may be NULL (DOP853's defaults: safety 0.9, fac1 0.333, fac2 6, beta 0); otherwise fill it
 * with ss_dop853_options_default() first and change what you need. */
int ss_dop853(ss_rhs f, void *data, int n, double t0, const double *y0, double t_end, int ntol,
              const double *rtol, const double *atol, const ss_dopri5_options *opts, int n_out,
              double *t_out, double *y_out, ss_stats *stats);

/* The same with the library's classical RK4, fixed step h (opts: max_steps and every_step
 * only; NULL: no step budget). */
int ss_rk4(ss_rhs f, void *data, int n, double t0, const double *y0, double t_end, double h,
           const ss_dopri5_options *opts, int n_out, double *t_out, double *y_out, ss_stats *stats);

/* ---- Periodic orbits: single shooting with Newton at a section (stickslip_orbit).
 *
 * The unknowns are the state y0 at the section's time t0 (opts->t0, default 0: each run goes
 * from t0 to t0 + period) and, when autonomous = 1, the period (a phase
 * condition fixes the section: y0 - guess orthogonal to the flow at the guess); with
 * autonomous = 0 the period is the forcing period. Each residual is one run of the method;
 * the Jacobian by forward differences (increment fd_newton times each unknown's scale), the
 * Newton step halved up to 12 times until the residual's infinity norm decreases; converged
 * when it is at most tol * max(1, |guess|_inf). The monodromy (d y(T) / d y0) by central
 * differences of the same method's flow, increment fd_monodromy times each component's
 * scale (positions share max(|x|_inf, 1e-3), velocities max(|v|_inf, 1e-3), law states
 * max(|z|_inf, 1e-9)); the Floquet multipliers are its eigenvalues (Hessenberg QR),
 * largest modulus first. Failures: SS_NO_ORBIT (info->residual tells how far),
 * SS_ORBIT_COLLAPSED (the period fell below 1e-3 of its guess), SS_BAD_PERIOD,
 * SS_BAD_GUESS (n is not the system's state size, or a value is not finite),
 * SS_BAD_ORBIT_OPTION, and any code of ss_run / ss_model_simulate. */
typedef struct {
    double tol;           /* Newton's tolerance, relative to max(1, |guess|_inf) (1e-9) */
    int max_iter;         /* Newton iterations at most (30; 0: the monodromy at the guess) */
    double fd_newton;     /* forward-difference increment of the Jacobian, relative (1e-5) */
    double fd_monodromy;  /* central-difference increment of the monodromy, relative (1e-4) */
    double t0;            /* the section's time [s]: y0 is the state at t = t0 (0); finite */
} ss_orbit_options;

typedef struct {
    double period;     /* the period [s] */
    double residual;   /* the shooting residual's infinity norm at the answer [state units] */
    int iterations;    /* Newton iterations made */
    int runs;          /* runs of the method made */
    int trivial;       /* index (from 0) of the trivial multiplier (autonomous); -1 when forced */
    int stable;        /* 1: every nontrivial multiplier inside the unit circle */
} ss_orbit_info;

void ss_orbit_options_default(ss_orbit_options *o);

/* A scene with a law (codes; parameters by name as in ss_run). y0[n]: the guess of the state
 * at the section on entry, the orbit's on return (the last iterate when Newton failed;
 * untouched for bad input). period [s]: the forcing period, or with autonomous = 1 the guess
 * of the period (the answer in info->period). opts NULL: defaults. monodromy[n * n] (row i:
 * d y_i(T) / d y0_j), mult_re[n], mult_im[n] and info may each be NULL; with the three arrays
 * NULL no monodromy is computed. */
int ss_periodic_orbit(int scene, int law, int method, const char *pkeys, int np, const double *pvals,
                      int n, double *y0, double period, int autonomous, int ntol, const double *rtol,
                      const double *atol, const char *ckeys, int nc, const double *cvals,
                      const ss_orbit_options *opts, double *monodromy, double *mult_re, double *mult_im,
                      ss_orbit_info *info);

/* ---- Your own system: a model of bodies, springs, dampers, forces, signals and friction contacts.
 *
 * The model of stickslip_user_model (Fortran) and stickslip.Model (Python) behind an opaque
 * handle: ss_model_new() makes one, ss_model_free() frees it. Bodies, elements and signals
 * are numbered from 1 in the order they are added, each kind on its own; SS_GROUND (0) is the
 * ground as a body, SS_NO_SIGNAL (0) no surface velocity. The ss_model_add_* and ss_signal_*
 * functions return the new element's index (>= 1) or a negative status (SS_BAD_HANDLE for
 * a NULL or dead handle, SS_BAD_DIM for an array argument that cannot be read); the model's
 * values are checked as a whole by ss_model_check() and ss_model_simulate(), which return the
 * first bad element's status (SS_BAD_MODEL_EMPTY, SS_BAD_BODY, SS_BAD_MASS, SS_BAD_SPRING,
 * SS_BAD_DAMPER, SS_BAD_SIGNAL, SS_BAD_LAW, a law parameter's SS_BAD_*) and keep its kind
 * (SS_ELEM_*) and index for ss_model_error() and ss_model_message() ("contact 1 (body 1 -
 * ground): mu_k: ..."). A handle may be used by one thread at a time; different handles
 * by different threads at once. Units are SI: mass [kg] (or an inertia [kg m^2] with
 * positions in rad), positions [m], velocities [m/s], forces [N], times [s]. */
typedef struct ss_model ss_model;

/* A new empty model, or NULL when out of memory. */
ss_model *ss_model_new(void);
/* Free a model (NULL: nothing); the handle is dead afterwards. */
void ss_model_free(ss_model *m);

/* A body of mass (or inertia) mass [kg] > 0 at x0 [m] moving at v0 [m/s]: its index. */
int ss_model_add_body(ss_model *m, double mass, double x0, double v0);
/* A spring k [N/m] >= 0 between bodies a and b (SS_GROUND: the ground), relaxed at
 * x_a - x_b = rest_length [m]: its index. */
int ss_model_add_spring(ss_model *m, int a, int b, double k, double rest_length);
/* A damper c [N s/m] >= 0 between bodies a and b (SS_GROUND: the ground): its index. */
int ss_model_add_damper(ss_model *m, int a, int b, double c);
/* The force of a signal [N] on a body: its index. */
int ss_model_add_force(ss_model *m, int body, int signal);
/* A friction contact between bodies a and b (SS_GROUND: the ground): the friction force on a
 * opposes the slip v_a - v_b - w, with w the signal surface_velocity [m/s] (SS_NO_SIGNAL: 0),
 * and b gets the opposite force; the signal normal_force [N] <= 0 opens the contact. The law
 * by code (SS_LAW_*, ss_code("law", name)) with its parameters by name as in ss_run: pkeys
 * comma-separated ("mu_s,mu_k"; NULL or "" for none) valued by pvals[np]; the others take
 * their defaults. Returns the contact's index. */
int ss_model_add_contact(ss_model *m, int a, int b, int law, int normal_force, int surface_velocity,
                         const char *pkeys, int np, const double *pvals);

/* Prescribe the motion of a body by a signal, exactly under every method: its position [m]
 * (kind SS_DRIVE_POSITION; a signal without steps) or its velocity [m/s] (SS_DRIVE_VELOCITY;
 * its position is then x0 plus the signal's integral: sums, differences and multiples of
 * steps, ramps, sines and tables). The body leaves the state: every element joined to it acts
 * on the other body as an element on the ground plus a signal. Returns the drive's index. */
int ss_model_add_drive(ss_model *m, int body, int kind, int signal);

/* Signals of a model (forces [N], normal forces [N], surface velocities [m/s] as functions of
 * time, evaluated in the library); each returns the new signal's index. */
int ss_signal_constant(ss_model *m, double c);
/* before for t < time [s], after from t = time on (a time event for event_driven). */
int ss_signal_step(ss_model *m, double time, double before, double after);
/* 0 up to start [s], rising linearly by height over duration [s] > 0, then height. */
int ss_signal_ramp(ss_model *m, double start, double duration, double height);
/* amplitude sin(2 pi frequency t + phase) + offset; frequency [Hz], phase [rad]. */
int ss_signal_sine(ss_model *m, double amplitude, double frequency, double phase, double offset);
/* Linear between the points (t[i] [s], values[i]), i < n, t strictly increasing; held
 * constant outside. */
int ss_signal_table(ss_model *m, int n, const double *t, const double *values);
/* s1 + s2, s1 - s2, s1 * s2 of two signals of the model. */
int ss_signal_add(ss_model *m, int s1, int s2);
int ss_signal_sub(ss_model *m, int s1, int s2);
int ss_signal_mul(ss_model *m, int s1, int s2);

/* Check every element: SS_OK or the first bad element's status. */
int ss_model_check(ss_model *m);
/* The status of the last ss_model_check or ss_model_simulate, and the kind (SS_ELEM_*, 0 for
 * none) and index (from 1, 0 for none) of the element it names (either pointer may be NULL). */
int ss_model_error(const ss_model *m, int *elem_kind, int *elem_index);
/* That status's message naming the element, copied as ss_message does; its full length. */
int ss_model_message(const ss_model *m, char *buf, size_t buflen);

/* Run the model from t = 0 (the bodies' x0, v0) to t_end [s] with a method by code
 * (SS_METHOD_*). h: the step of the fixed-step methods (rk4, implicit_euler, galpha, moreau)
 * [s], ignored by the others (an "h" in ckeys wins); rtol, atol: the tolerances of the
 * adaptive methods; the other controls by name as in ss_run (ckeys, nc, cvals; NULL or ""
 * for none). t_out[n_out]: output times (non-decreasing, in [0, t_end]), or with the control
 * every_step room for every step (overwritten with the step times; stats->n_written rows).
 * x, v [n_bodies * n_out]: positions [m] and velocities [m/s], x[(j - 1) * n_out + i] = body j
 * at t_out[i]. events [4 * events_room]: the stick/slip events of event_driven, row k =
 * (t [s], kind SS_EVENT_STICK / _SLIP / _REVERSAL, the contact's displacement [m], contact
 * index from 1); NULL with events_room = 0 for none. *n_events: the run's events (may exceed
 * events_room; NULL: not returned). stats may be NULL. Returns stats->status; x, v are
 * untouched when an input is bad. moreau and event_driven take coulomb and stribeck contacts
 * only (SS_NOT_SETVALUED otherwise). */
int ss_model_simulate(ss_model *m, int method, double t_end, double h, double rtol, double atol,
                      const char *ckeys, int nc, const double *cvals, int n_out, double *t_out,
                      double *x, double *v, ss_stats *stats, int events_room, double *events,
                      int64_t *n_events);
/* The forces [N] the drives applied to their bodies in the last ss_model_simulate, m_d a_d
 * minus the other forces on the driven body: force[(d - 1) * n_out + i] = drive d at
 * t_out[i], n = n_drives * n_out (a stuck contact's holding force from the contact solver's
 * problem at rest under event_driven and moreau; NaN where a contact joins a driven body under
 * implicit_euler or galpha with coulomb or karnopp). SS_OK, or SS_BAD_DIM for another n. */
int ss_model_drive_forces(ss_model *m, int n, double *force);

/* A periodic orbit of a model, y0[n] = (x of every body, v of every body): h, rtol, atol,
 * ckeys, nc, cvals as for ss_model_simulate; the rest as for ss_periodic_orbit. A bad element
 * is named as by ss_model_check (ss_model_error, ss_model_message). */
int ss_model_periodic_orbit(ss_model *m, int method, int n, double *y0, double period, int autonomous,
                            double h, double rtol, double atol, const char *ckeys, int nc,
                            const double *cvals, const ss_orbit_options *opts, double *monodromy,
                            double *mult_re, double *mult_im, ss_orbit_info *info);

#ifdef __cplusplus
}
#endif

#endif /* STICKSLIP_H */
