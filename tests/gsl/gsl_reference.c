/* Independent reference runs with GSL's gsl_odeiv2 steppers on the belt and slope scenes.
 *
 * The scenes and friction laws are re-implemented here from the paper's formulas, in C,
 * so that a test compares two independent codes. GSL is GPL: this program is a test
 * tool only, never linked into the stickslip library.
 *
 * usage: gsl_reference STEPPER SCENE LAW T_END H_OR_TOL N_OUT
 *   STEPPER  rk4 (fixed step h; GSL's rk4 does step doubling: one step of h is two
 *            classical steps of h/2) | rk8pd | rkf45 | rkck (adaptive, tolerance rtol = atol)
 *   SCENE    slope | belt       LAW coulomb | recurdyn | proposed
 * Prints "t x v" for N_OUT uniform times on [0, T_END], then "# nfev=N nstep=N".
 * Parameters are the paper's (Table 1), v_d = 1.5 v_s, theta = 10 deg, k = 300, v_b = 1.5.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

typedef struct {
    int belt, law;
    double mu_s, mu_k, v_s, v_d, beta, a, g, theta, m, k, v_b;
    long nfev;
} scene;

static double havsin(double x, double x0, double h0, double x1, double h1) {
    if (x <= x0) return h0;
    if (x >= x1) return h1;
    return h0 + (h1 - h0) * 0.5 * (1.0 - cos(M_PI * (x - x0) / (x1 - x0)));
}

static double mu(const scene *s, double v) {
    double av = fabs(v), m;
    if (v == 0.0) return 0.0;
    if (s->law == 0) {
        m = av < s->v_s ? s->mu_s : s->mu_k;
    } else if (s->law == 1) {
        m = av < s->v_s ? havsin(av, 0.0, 0.0, s->v_s, s->mu_s) : havsin(av, s->v_s, s->mu_s, s->v_d, s->mu_k);
    } else {
        double b = -log(s->mu_s - s->mu_k) / log(s->a) - s->v_s;
        m = av <= s->v_s ? s->mu_s * pow(av / s->v_s, s->beta) : pow(s->a, -(av + b)) + s->mu_k;
    }
    return v > 0.0 ? m : -m;
}

static int rhs(double t, const double y[], double f[], void *params) {
    scene *s = (scene *)params;
    (void)t;
    s->nfev++;
    f[0] = y[1];
    if (s->belt)
        f[1] = -s->k / s->m * y[0] + mu(s, s->v_b - y[1]) * s->g;
    else
        f[1] = s->g * sin(s->theta) - mu(s, y[1]) * s->g * cos(s->theta);
    return GSL_SUCCESS;
}

int main(int argc, char **argv) {
    if (argc != 7) {
        fprintf(stderr, "usage: %s rk4|rk8pd|rkf45|rkck slope|belt coulomb|recurdyn|proposed T_END H_OR_TOL N_OUT\n", argv[0]);
        return 2;
    }
    scene s = {0};
    s.belt = strcmp(argv[2], "belt") == 0;
    s.law = strcmp(argv[3], "coulomb") == 0 ? 0 : strcmp(argv[3], "recurdyn") == 0 ? 1 : 2;
    s.mu_s = 0.35; s.mu_k = 0.30; s.v_s = 0.01; s.v_d = 0.015; s.beta = 1.0 / 3.0; s.a = 1.5;
    s.g = 9.81; s.theta = 10.0 * M_PI / 180.0; s.m = 10.0; s.k = 300.0; s.v_b = 1.5;
    double t_end = atof(argv[4]), hp = atof(argv[5]);
    int n_out = atoi(argv[6]);
    if (t_end <= 0.0 || hp <= 0.0 || n_out < 2) {
        fprintf(stderr, "T_END, H_OR_TOL must be > 0 and N_OUT >= 2\n");
        return 2;
    }
    gsl_odeiv2_system sys = {rhs, NULL, 2, &s};
    double y[2] = {0.0, 0.0}, t = 0.0;
    long nstep = 0;
    printf("%.17g %.17g %.17g\n", t, y[0], y[1]);
    if (strcmp(argv[1], "rk4") == 0) {
        /* Drive the stepper directly: one call per step, no error control, status checked. */
        gsl_odeiv2_step *st = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk4, 2);
        double yerr[2];
        long n = lround(t_end / hp);
        long per_out = n / (n_out - 1);
        if (per_out * (n_out - 1) != n || fabs(n * hp - t_end) > 1e-9 * t_end) {
            fprintf(stderr, "T_END / H must be an integer multiple of N_OUT - 1\n");
            return 2;
        }
        for (long i = 1; i <= n; i++) {
            int status = gsl_odeiv2_step_apply(st, t, hp, y, yerr, NULL, NULL, &sys);
            if (status != GSL_SUCCESS) {
                fprintf(stderr, "gsl_odeiv2_step_apply failed: %s\n", gsl_strerror(status));
                return 1;
            }
            t = i * hp;
            nstep++;
            if (i % per_out == 0) printf("%.17g %.17g %.17g\n", t, y[0], y[1]);
        }
        gsl_odeiv2_step_free(st);
    } else {
        const gsl_odeiv2_step_type *type = strcmp(argv[1], "rk8pd") == 0 ? gsl_odeiv2_step_rk8pd
                                         : strcmp(argv[1], "rkf45") == 0 ? gsl_odeiv2_step_rkf45
                                         : gsl_odeiv2_step_rkck;
        gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, type, 1e-6, hp, hp);
        for (int i = 1; i < n_out; i++) {
            double ti = t_end * i / (n_out - 1);
            int status = gsl_odeiv2_driver_apply(d, &t, ti, y);
            if (status != GSL_SUCCESS) {
                fprintf(stderr, "gsl_odeiv2_driver_apply failed at t=%g: %s\n", t, gsl_strerror(status));
                return 1;
            }
            printf("%.17g %.17g %.17g\n", t, y[0], y[1]);
        }
        nstep = (long)d->n;
        gsl_odeiv2_driver_free(d);
    }
    printf("# nfev=%ld nstep=%ld\n", s.nfev, nstep);
    return 0;
}
