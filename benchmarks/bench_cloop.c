/* The practical limit: a plain C loop doing the classical RK4 arithmetic on a scene, with the
 * parameters in runtime variables. No error checks, no output grid, no counters in the loop.
 * usage: bench_cloop SCENE LAW rk4 T_END H REPEATS MIN_SAMPLE_S  (see bench_common.h) */
#include "bench_common.h"

static long run(const bench_scene *s, double t_end, double h, double y[2]) {
    long n = (long)ceil(t_end / h * (1.0 - 1e-12));
    double k1[2], k2[2], k3[2], k4[2], yt[2];
    y[0] = 0.0;
    y[1] = 0.0;
    double t = 0.0;
    for (long i = 1; i <= n; i++) {
        double t1 = i == n ? t_end : i * h, hs = t1 - t;
        bench_rhs(s, y, k1);
        yt[0] = y[0] + 0.5 * hs * k1[0];
        yt[1] = y[1] + 0.5 * hs * k1[1];
        bench_rhs(s, yt, k2);
        yt[0] = y[0] + 0.5 * hs * k2[0];
        yt[1] = y[1] + 0.5 * hs * k2[1];
        bench_rhs(s, yt, k3);
        yt[0] = y[0] + hs * k3[0];
        yt[1] = y[1] + hs * k3[1];
        bench_rhs(s, yt, k4);
        y[0] += hs / 6.0 * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0]);
        y[1] += hs / 6.0 * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1]);
        t = t1;
    }
    return n;
}

static double timed(void *ctx, long n) {
    bench_args *a = (bench_args *)ctx;
    double y[2], t0 = bench_now();
    for (long j = 0; j < n; j++) run(&a->s, a->t_end, a->h_or_tol, y);
    return bench_now() - t0;
}

int main(int argc, char **argv) {
    bench_args a;
    if (bench_parse(argc, argv, &a)) return 2;
    if (strcmp(a.method, "rk4") != 0) {
        fprintf(stderr, "bench_cloop: only rk4\n");
        return 2;
    }
    double y[2], *samples = malloc(sizeof(double) * a.repeats);
    long nstep = 0;
    double t0 = bench_now();
    nstep = run(&a.s, a.t_end, a.h_or_tol, y); /* warm-up and calibration */
    double once = bench_now() - t0;
    long inner = bench_inner(once, a.min_sample, timed, &a);
    for (int r = 0; r < a.repeats; r++) {
        t0 = bench_now();
        for (long j = 0; j < inner; j++) run(&a.s, a.t_end, a.h_or_tol, y);
        samples[r] = (bench_now() - t0) / inner;
    }
    printf("%.9e %ld %ld %.17g %.17g\n", median(samples, a.repeats), 4 * nstep, nstep, y[0], y[1]);
    free(samples);
    return 0;
}
