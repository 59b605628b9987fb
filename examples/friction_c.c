/* Call stickslip's friction laws and simulate its scenes from C, through stickslip.h.
 *
 * Build against an installed stickslip:
 *     cc friction_c.c $(pkg-config --cflags --libs stickslip)
 * Prints key=value lines (and "mu LAW V MU" lines for the friction coefficients).
 */
#include <math.h>
#include <stdio.h>
#include <stickslip.h>

/* A user's own ODE for ss_dopri5: y' = -lambda y, y(t) = exp(-lambda t) y0. */
static void decay(double t, const double *y, double *dydt, int n, void *data) {
    double lambda = *(const double *)data;
    (void)t;
    for (int i = 0; i < n; i++) dydt[i] = -lambda * y[i];
}

static int check(const char *what, int status) {
    char msg[256];
    if (status != SS_OK) {
        ss_message(status, msg, sizeof msg);
        fprintf(stderr, "%s failed: %s (status %d)\n", what, msg, status);
    }
    return status;
}

int main(void) {
    ss_params p;
    ss_params_default(&p);

    /* Friction coefficients at a few relative velocities [m/s]. */
    const double v[] = {-1.5, -0.02, -0.005, 0.0, 0.005, 0.0125, 0.02, 1.5};
    const int nv = (int)(sizeof v / sizeof v[0]);
    const char *names[] = {"", "coulomb", "recurdyn", "proposed"};
    double mu[8];
    for (int law = SS_LAW_COULOMB; law <= SS_LAW_PROPOSED; law++) {
        if (check("ss_friction", ss_friction(law, nv, v, p.mu_s, p.mu_k, p.v_s, p.v_d, p.beta, p.a, mu)))
            return 1;
        for (int i = 0; i < nv; i++) printf("mu %s %.17g %.17g\n", names[law], v[i], mu[i]);
    }

    /* A bad parameter comes back as a status with a message naming it. */
    char msg[256];
    int bad = ss_friction(SS_LAW_PROPOSED, nv, v, 0.3, 0.35, p.v_s, p.v_d, p.beta, p.a, mu);
    ss_message(bad, msg, sizeof msg);
    printf("bad_status=%d\nbad_message=%s\n", bad, msg);

    /* The belt scene with the proposed law: DOPRI5 and RK4 over 20 s, 201 output times. */
    enum { NOUT = 201 };
    double t_out[NOUT], y_out[2 * NOUT];
    ss_stats st;
    ss_dopri5_options opts;
    ss_dopri5_options_default(&opts);
    opts.hmin = 1e-6;
    opts.hmax = 1e-2;
    for (int i = 0; i < NOUT; i++) t_out[i] = 20.0 * i / (NOUT - 1);
    if (check("ss_simulate dopri5", ss_simulate(SS_SCENE_BELT, SS_LAW_PROPOSED, SS_METHOD_DOPRI5, &p,
                                                0.0, 0.0, 20.0, 0.0, 1e-8, 1e-10, &opts, NOUT, t_out,
                                                y_out, &st)))
        return 1;
    double xmax = 0.0;
    for (int i = NOUT / 2; i < NOUT; i++) xmax = fmax(xmax, y_out[2 * i]);
    printf("belt_dopri5_x_end=%.17g\nbelt_dopri5_v_end=%.17g\nbelt_dopri5_xmax_late=%.17g\n",
           y_out[2 * (NOUT - 1)], y_out[2 * (NOUT - 1) + 1], xmax);
    printf("belt_dopri5_nfev=%lld\nbelt_dopri5_nstep=%lld\nbelt_dopri5_naccept=%lld\n"
           "belt_dopri5_nreject=%lld\nbelt_dopri5_nforced=%lld\nbelt_dopri5_n_written=%d\n",
           (long long)st.nfev, (long long)st.nstep, (long long)st.naccept, (long long)st.nreject,
           (long long)st.nforced, st.n_written);

    if (check("ss_simulate rk4", ss_simulate(SS_SCENE_BELT, SS_LAW_PROPOSED, SS_METHOD_RK4, &p, 0.0,
                                             0.0, 20.0, 1e-4, 0.0, 0.0, NULL, NOUT, t_out, y_out, &st)))
        return 1;
    printf("belt_rk4_x_end=%.17g\nbelt_rk4_v_end=%.17g\nbelt_rk4_nfev=%lld\nbelt_rk4_nstep=%lld\n",
           y_out[2 * (NOUT - 1)], y_out[2 * (NOUT - 1) + 1], (long long)st.nfev, (long long)st.nstep);

    /* The slope scene: the box should stay (nearly) put. */
    if (check("ss_simulate slope", ss_simulate(SS_SCENE_SLOPE, SS_LAW_PROPOSED, SS_METHOD_DOPRI5, &p, 0.0,
                                               0.0, 20.0, 0.0, 1e-8, 1e-10, &opts, NOUT, t_out, y_out,
                                               &st)))
        return 1;
    printf("slope_proposed_x_end=%.17g\n", y_out[2 * (NOUT - 1)]);

    /* Any law, scene and method of the registry by name, parameters and controls by name:
     * the same slope run through ss_run, then the implicit RADAU5 on the RecurDyn law. */
    double x_struct = y_out[2 * (NOUT - 1)];
    double y0s[2] = {0.0, 0.0}, rtol = 1e-8, atol = 1e-10;
    double ctl[2] = {1e-6, 1e-2};
    if (check("ss_run dopri5", ss_run(ss_code("scene", "slope"), ss_code("law", "proposed"),
                                      ss_code("method", "dopri5"), "", 0, NULL, 2, y0s, 20.0, 1, &rtol,
                                      &atol, "hmin,hmax", 2, ctl, NOUT, t_out, y_out, &st)))
        return 1;
    printf("slope_proposed_by_name_equal=%d\n", y_out[2 * (NOUT - 1)] == x_struct);
    double vs = 0.02, rtol5 = 1e-6, atol5 = 1e-9;
    if (check("ss_run radau5", ss_run(SS_SCENE_SLOPE, ss_code("law", "recurdyn"), SS_METHOD_RADAU5, "v_s", 1,
                                      &vs, 2, y0s, 20.0, 1, &rtol5, &atol5, "", 0, NULL, NOUT, t_out, y_out, &st)))
        return 1;
    printf("slope_recurdyn_radau5_v_end=%.17g\nslope_recurdyn_radau5_njac=%lld\n", y_out[2 * (NOUT - 1) + 1],
           (long long)st.njac);
    printf("unknown_law_code=%d\n", ss_code("law", "no-such-law"));

    /* Your own ODE with the library's DOPRI5, through a C function pointer. */
    double lambda = 2.0, y0 = 1.0, t1[1] = {1.0}, y1[1], tol = 1e-10;
    if (check("ss_dopri5", ss_dopri5(decay, &lambda, 1, 0.0, &y0, 1.0, 1, &tol, &tol, NULL, 1, t1, y1, &st)))
        return 1;
    printf("decay_y_end=%.17g\ndecay_exact=%.17g\ndecay_nfev=%lld\ndecay_nstep=%lld\n", y1[0],
           exp(-lambda), (long long)st.nfev, (long long)st.nstep);

    /* ... with the library's DOP853, at its defaults and with a struct at the same defaults */
    ss_dopri5_options o8;
    ss_dop853_options_default(&o8);
    double y8[1];
    if (check("ss_dop853", ss_dop853(decay, &lambda, 1, 0.0, &y0, 1.0, 1, &tol, &tol, NULL, 1, t1, y1, &st)) ||
        check("ss_dop853 opts", ss_dop853(decay, &lambda, 1, 0.0, &y0, 1.0, 1, &tol, &tol, &o8, 1, t1, y8, NULL)))
        return 1;
    printf("decay_dop853_y_end=%.17g\ndecay_dop853_nfev=%lld\ndecay_dop853_nstep=%lld\n"
           "decay_dop853_opts_equal=%d\n", y1[0], (long long)st.nfev, (long long)st.nstep, y8[0] == y1[0]);

    /* ... and with the library's RK4 at h = 0.01 (global error about lambda^5 h^4 t / 120 y). */
    if (check("ss_rk4", ss_rk4(decay, &lambda, 1, 0.0, &y0, 1.0, 0.01, NULL, 1, t1, y1, &st)))
        return 1;
    printf("decay_rk4_y_end=%.17g\ndecay_rk4_nfev=%lld\ndecay_rk4_nstep=%lld\n", y1[0],
           (long long)st.nfev, (long long)st.nstep);
    return 0;
}
