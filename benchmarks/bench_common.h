/* Shared by the C benchmark programs: command line, the paper's parameters, the friction laws
 * written from the paper (eqs. 1, 2-3, 5) with b and ln a of the proposed law precomputed, the
 * two scenes, and a timer that reports the median of several samples.
 *
 * Every program prints one line: "median_s nfev nstep x_end v_end", where median_s is the
 * median over REPEATS samples of the time of one integration [s]; each sample repeats the
 * integration until it lasts at least MIN_SAMPLE_S (bench_inner). With MIN_SAMPLE_S = 0 a
 * program runs the integration exactly 1 + REPEATS times, which is how the benchmark driver
 * counts instructions per integration under callgrind (the difference of two REPEATS).
 */
#ifndef BENCH_COMMON_H
#define BENCH_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    int belt, law; /* law: 1 coulomb, 2 recurdyn, 3 proposed */
    double mu_s, mu_k, v_s, v_d, beta, ln_a, b, g_sin, g_cos, k_m, g, v_b;
    long nfev;
} bench_scene;

typedef struct {
    bench_scene s;
    const char *method;
    double t_end, h_or_tol, min_sample;
    int repeats;
} bench_args;

static int bench_parse(int argc, char **argv, bench_args *a) {
    if (argc != 8) {
        fprintf(stderr, "usage: %s SCENE LAW METHOD T_END H_OR_TOL REPEATS MIN_SAMPLE_S\n", argv[0]);
        return 2;
    }
    bench_scene *s = &a->s;
    memset(s, 0, sizeof *s);
    s->belt = strcmp(argv[1], "belt") == 0;
    s->law = strcmp(argv[2], "coulomb") == 0 ? 1 : strcmp(argv[2], "recurdyn") == 0 ? 2 : 3;
    /* Runtime values (the paper's Table 1), never compile-time constants in the loops. */
    double theta = strtod("10.0", NULL) * M_PI / 180.0, m = strtod("10.0", NULL);
    s->mu_s = strtod("0.35", NULL);
    s->mu_k = strtod("0.30", NULL);
    s->v_s = strtod("0.01", NULL);
    s->v_d = 1.5 * s->v_s;
    s->beta = 1.0 / 3.0;
    s->ln_a = log(strtod("1.5", NULL));
    s->b = -log(s->mu_s - s->mu_k) / s->ln_a - s->v_s;
    s->g = strtod("9.81", NULL);
    s->g_sin = s->g * sin(theta);
    s->g_cos = s->g * cos(theta);
    s->k_m = strtod("300.0", NULL) / m;
    s->v_b = strtod("1.5", NULL);
    a->method = argv[3];
    a->t_end = atof(argv[4]);
    a->h_or_tol = atof(argv[5]);
    a->repeats = atoi(argv[6]);
    a->min_sample = atof(argv[7]);
    if (a->t_end <= 0.0 || a->h_or_tol <= 0.0 || a->repeats < 1) {
        fprintf(stderr, "T_END, H_OR_TOL must be > 0 and REPEATS >= 1\n");
        return 2;
    }
    return 0;
}

static inline double havsin(double x, double x0, double h0, double x1, double h1) {
    if (x <= x0) return h0;
    if (x >= x1) return h1;
    return h0 + (h1 - h0) * 0.5 * (1.0 - cos(M_PI * (x - x0) / (x1 - x0)));
}

static inline double bench_mu(const bench_scene *s, double v) {
    double av = fabs(v), m;
    if (s->law == 1) {
        if (v == 0.0) return 0.0;
        m = av < s->v_s ? s->mu_s : s->mu_k;
    } else if (s->law == 2) {
        m = av < s->v_s ? havsin(av, 0.0, 0.0, s->v_s, s->mu_s) : havsin(av, s->v_s, s->mu_s, s->v_d, s->mu_k);
    } else {
        m = av <= s->v_s ? s->mu_s * pow(av / s->v_s, s->beta) : exp(-s->ln_a * (av + s->b)) + s->mu_k;
    }
    return copysign(m, v);
}

static inline void bench_rhs(const bench_scene *s, const double y[2], double f[2]) {
    f[0] = y[1];
    if (s->belt)
        f[1] = -s->k_m * y[0] + bench_mu(s, s->v_b - y[1]) * s->g;
    else
        f[1] = s->g_sin - bench_mu(s, y[1]) * s->g_cos;
}

static double bench_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Runs per sample, so that a sample lasts at least min_sample seconds. `once` is the time of
 * the first run, which is cold (page faults, lazy binding) and would make samples too short;
 * a warm batch of about a tenth of a sample times one run again. timed(ctx, n) returns the
 * seconds of n runs. min_sample = 0 (counting instructions): one run, no calibration. */
static long bench_inner(double once, double min_sample, double (*timed)(void *, long), void *ctx) {
    if (min_sample <= 0.0) return 1;
    long n = once > 0.0 ? (long)ceil(0.1 * min_sample / once) : 1;
    if (n < 1) n = 1;
    double warm = timed(ctx, n) / n;
    long inner = warm > 0.0 ? (long)ceil(min_sample / warm) : n;
    return inner < 1 ? 1 : inner;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *x, int n) {
    qsort(x, n, sizeof *x, cmp_double);
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

#endif
