/* GSL's gsl_odeiv2 on a scene: rk4 (fixed step h, driven by gsl_odeiv2_step_apply; note GSL's
 * rk4 does step doubling, so one step of h costs about 11-12 evaluations), or the adaptive
 * rkf45, rkck, rk8pd through gsl_odeiv2_driver_apply with eps_abs = eps_rel = TOL.
 * GSL is GPL: this program is a benchmark only, never linked into the stickslip library.
 * usage: bench_gsl SCENE LAW rk4|rkf45|rkck|rk8pd T_END H_OR_TOL REPEATS MIN_SAMPLE_S */
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include "bench_common.h"

static int rhs(double t, const double y[], double f[], void *params) {
    bench_scene *s = (bench_scene *)params;
    (void)t;
    s->nfev++;
    bench_rhs(s, y, f);
    return GSL_SUCCESS;
}

/* One integration from rest; returns 0 or a GSL error. */
static int run(bench_args *a, double y[2], long *nstep) {
    gsl_odeiv2_system sys = {rhs, NULL, 2, &a->s};
    double t = 0.0;
    int status = GSL_SUCCESS;
    y[0] = 0.0;
    y[1] = 0.0;
    a->s.nfev = 0;
    *nstep = 0;
    if (strcmp(a->method, "rk4") == 0) {
        gsl_odeiv2_step *st = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk4, 2);
        double yerr[2], h = a->h_or_tol;
        long n = (long)ceil(a->t_end / h * (1.0 - 1e-12));
        for (long i = 1; i <= n && status == GSL_SUCCESS; i++) {
            double t1 = i == n ? a->t_end : i * h;
            status = gsl_odeiv2_step_apply(st, t, t1 - t, y, yerr, NULL, NULL, &sys);
            t = t1;
            (*nstep)++;
        }
        gsl_odeiv2_step_free(st);
    } else {
        const gsl_odeiv2_step_type *type = strcmp(a->method, "rk8pd") == 0 ? gsl_odeiv2_step_rk8pd
                                         : strcmp(a->method, "rkf45") == 0 ? gsl_odeiv2_step_rkf45
                                         : gsl_odeiv2_step_rkck;
        gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, type, 1e-6, a->h_or_tol, a->h_or_tol);
        gsl_odeiv2_driver_set_nmax(d, 100000000);
        status = gsl_odeiv2_driver_apply(d, &t, a->t_end, y);
        *nstep = (long)d->n;
        gsl_odeiv2_driver_free(d);
    }
    return status;
}

static double timed(void *ctx, long n) {
    double y[2], t0 = bench_now();
    long nstep;
    for (long j = 0; j < n; j++) run((bench_args *)ctx, y, &nstep);
    return bench_now() - t0;
}

int main(int argc, char **argv) {
    bench_args a;
    if (bench_parse(argc, argv, &a)) return 2;
    gsl_set_error_handler_off();
    double y[2], *samples = malloc(sizeof(double) * a.repeats);
    long nstep;
    double t0 = bench_now();
    int status = run(&a, y, &nstep);
    double once = bench_now() - t0;
    if (status != GSL_SUCCESS) {
        fprintf(stderr, "bench_gsl: %s\n", gsl_strerror(status));
        return 1;
    }
    long nfev = a.s.nfev;
    long inner = bench_inner(once, a.min_sample, timed, &a);
    for (int r = 0; r < a.repeats; r++) {
        t0 = bench_now();
        for (long j = 0; j < inner; j++) run(&a, y, &nstep);
        samples[r] = (bench_now() - t0) / inner;
    }
    printf("%.9e %ld %ld %.17g %.17g\n", median(samples, a.repeats), nfev, nstep, y[0], y[1]);
    free(samples);
    return 0;
}
