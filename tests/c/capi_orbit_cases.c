/* Cases of the periodic-orbit C API (ss_periodic_orbit, ss_model_periodic_orbit) for
 * tests/fortran/test_stickslip_orbit.py, which checks them against closed forms, stickslip.periodic_orbit and
 * scipy's variational equations, and checks the status of every bad input.
 *
 * Prints one record per line, fields separated by blanks:
 *   orbit NAME status period residual iterations runs trivial stable n y0[n] re[n] im[n] M[n*n]
 *   case NAME status residual | message
 */
#include <math.h>
#include <stdio.h>
#include <stickslip.h>

static void print_orbit(const char *name, int status, int n, const double *y0, const double *re,
                        const double *im, const double *mono, const ss_orbit_info *info) {
    printf("orbit %s %d %.17g %.17g %d %d %d %d %d", name, status, info->period, info->residual,
           info->iterations, info->runs, info->trivial, info->stable, n);
    for (int i = 0; i < n; i++) printf(" %.17g", y0[i]);
    for (int i = 0; i < n; i++) printf(" %.17g", re[i]);
    for (int i = 0; i < n; i++) printf(" %.17g", im[i]);
    for (int i = 0; i < n * n; i++) printf(" %.17g", mono[i]);
    printf("\n");
}

static void print_case(const char *name, int status, double residual) {
    char msg[512] = "";
    ss_message(status, msg, sizeof msg);
    printf("case %s %d %.17g | %s\n", name, status, residual, msg);
}

/* Den Hartog's oscillator (m = k = 1, P0 cos(beta t), Coulomb F = r): a model. */
static ss_model *den_hartog(double beta, double r) {
    ss_model *m = ss_model_new();
    int b = ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_spring(m, b, SS_GROUND, 1.0, 0.0);
    ss_model_add_force(m, b, ss_signal_sine(m, 1.0, beta / (2.0 * M_PI), M_PI / 2.0, 0.0));
    const double mu[] = {1.0, 1.0};
    ss_model_add_contact(m, b, SS_GROUND, SS_LAW_COULOMB, ss_signal_constant(m, r), SS_NO_SIGNAL, "mu_s,mu_k", 2,
                         mu);
    return m;
}

/* A forced oscillator with a smooth law (proposed): m = 1, k = 4, 10 sin(2 pi 0.25 t), N = 9.81. */
static ss_model *smooth(void) {
    ss_model *m = ss_model_new();
    int b = ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_spring(m, b, SS_GROUND, 4.0, 0.0);
    ss_model_add_force(m, b, ss_signal_sine(m, 10.0, 0.25, 0.0, 0.0));
    const double p[] = {0.4, 0.3, 0.5};
    ss_model_add_contact(m, b, SS_GROUND, SS_LAW_PROPOSED, ss_signal_constant(m, 9.81), SS_NO_SIGNAL,
                         "mu_s,mu_k,v_s", 3, p);
    return m;
}

int main(void) {
    double y[2], re[2], im[2], mono[4], tol[] = {1e-12}, atol[] = {1e-14};
    ss_orbit_info info;
    int status;

    /* the belt's stick-slip cycle, autonomous, set-valued Coulomb under event_driven, from a
     * state in its stick phase and a period 10 % off */
    const double belt[] = {1.0, 4.0, 0.3, 9.81, 0.4, 0.3};
    y[0] = 0.8;
    y[1] = 0.3;
    status = ss_periodic_orbit(SS_SCENE_BELT, SS_LAW_COULOMB, SS_METHOD_EVENT_DRIVEN, "m,k,v_b,g,mu_s,mu_k", 6, belt,
                               2, y, 3.3, 1, 1, tol, atol, "", 0, NULL, NULL, mono, re, im, &info);
    print_orbit("belt", status, 2, y, re, im, mono, &info);

    /* Den Hartog, beta = 2, r = 0.3 (no stops): forced, event_driven, from rest */
    ss_model *dh = den_hartog(2.0, 0.3);
    y[0] = y[1] = 0.0;
    status = ss_model_periodic_orbit(dh, SS_METHOD_EVENT_DRIVEN, 2, y, M_PI, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL,
                                     NULL, mono, re, im, &info);
    print_orbit("den_hartog", status, 2, y, re, im, mono, &info);

    /* the same orbit with its section at t0 = 0.7 s: y0 the state at t = 0.7 */
    ss_orbit_options shifted;
    ss_orbit_options_default(&shifted);
    shifted.t0 = 0.7;
    y[0] = y[1] = 0.0;
    status = ss_model_periodic_orbit(dh, SS_METHOD_EVENT_DRIVEN, 2, y, M_PI, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL,
                                     &shifted, mono, re, im, &info);
    print_orbit("den_hartog_t0", status, 2, y, re, im, mono, &info);
    ss_model_free(dh);

    /* the smooth forced oscillator under dopri5, from a rough guess (the tolerance is relative
     * to max(1, |guess|): from rest it would be 1e-9 absolute, below the flow's own error) */
    ss_model *sm = smooth();
    y[0] = -2.0;
    y[1] = 8.0;
    status = ss_model_periodic_orbit(sm, SS_METHOD_DOPRI5, 2, y, 4.0, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL, NULL,
                                     mono, re, im, &info);
    print_orbit("smooth", status, 2, y, re, im, mono, &info);

    /* the smooth oscillator with its section at t0 = 1.3 s (a quarter and more of the period) */
    shifted.t0 = 1.3;
    y[0] = -2.0;
    y[1] = 8.0;
    status = ss_model_periodic_orbit(sm, SS_METHOD_DOPRI5, 2, y, 4.0, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL,
                                     &shifted, mono, re, im, &info);
    print_orbit("smooth_t0", status, 2, y, re, im, mono, &info);

    /* three bodies in a row, springs and dampers, the first forced: linear, 6 x 6 monodromy */
    ss_model *ch = ss_model_new();
    int b1 = ss_model_add_body(ch, 1.0, 0.0, 0.0), b2 = ss_model_add_body(ch, 2.0, 0.0, 0.0);
    int b3 = ss_model_add_body(ch, 0.5, 0.0, 0.0);
    ss_model_add_spring(ch, b1, SS_GROUND, 3.0, 0.0);
    ss_model_add_spring(ch, b1, b2, 2.0, 0.0);
    ss_model_add_spring(ch, b2, b3, 5.0, 0.0);
    ss_model_add_damper(ch, b1, SS_GROUND, 0.3);
    ss_model_add_damper(ch, b2, b3, 0.2);
    ss_model_add_force(ch, b1, ss_signal_sine(ch, 1.0, 0.4, 0.0, 0.0));
    double y6[6] = {0}, re6[6], im6[6], mono6[36];
    status = ss_model_periodic_orbit(ch, SS_METHOD_DOPRI5, 6, y6, 2.5, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL, NULL,
                                     mono6, re6, im6, &info);
    print_orbit("chain3", status, 6, y6, re6, im6, mono6, &info);
    ss_model_free(ch);

    /* bad input, each named */
    y[0] = y[1] = 0.0;
    status = ss_model_periodic_orbit(sm, SS_METHOD_DOPRI5, 2, y, -1.0, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL, NULL,
                                     NULL, NULL, NULL, &info);
    print_case("period", status, NAN);
    status = ss_model_periodic_orbit(sm, SS_METHOD_DOPRI5, 3, (double[]){0.0, 0.0, 0.0}, 4.0, 0, 0.0, 1e-12, 1e-14,
                                     NULL, 0, NULL, NULL, NULL, NULL, NULL, &info);
    print_case("guess", status, NAN);
    ss_orbit_options o;
    ss_orbit_options_default(&o);
    o.tol = 0.0;
    status = ss_model_periodic_orbit(sm, SS_METHOD_DOPRI5, 2, y, 4.0, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL, &o,
                                     NULL, NULL, NULL, &info);
    print_case("options", status, NAN);
    ss_orbit_options_default(&o);
    o.t0 = INFINITY;
    status = ss_model_periodic_orbit(sm, SS_METHOD_DOPRI5, 2, y, 4.0, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL, &o,
                                     NULL, NULL, NULL, &info);
    print_case("options_t0", status, NAN);
    status = ss_periodic_orbit(SS_SCENE_BELT, SS_LAW_COULOMB, SS_METHOD_EVENT_DRIVEN, "m", 1, belt, 2, y, 0.0, 1,
                               1, tol, atol, "", 0, NULL, NULL, NULL, NULL, NULL, &info);
    print_case("scene_period", status, NAN);
    status = ss_periodic_orbit(SS_SCENE_BELT, SS_LAW_COULOMB, SS_METHOD_EVENT_DRIVEN, "m", 1, belt, 1, y, 3.0, 1,
                               1, tol, atol, "", 0, NULL, NULL, NULL, NULL, NULL, &info);
    print_case("scene_guess", status, NAN);
    ss_model_free(sm);

    /* no orbit: an undamped oscillator forced at resonance (w = 2 rad/s) */
    ss_model *res = ss_model_new();
    int b = ss_model_add_body(res, 1.0, 0.0, 0.0);
    ss_model_add_spring(res, b, SS_GROUND, 4.0, 0.0);
    ss_model_add_force(res, b, ss_signal_sine(res, 1.0, 1.0 / M_PI, 0.0, 0.0));
    ss_orbit_options_default(&o);
    o.max_iter = 5;
    y[0] = y[1] = 0.0;
    status = ss_model_periodic_orbit(res, SS_METHOD_DOPRI5, 2, y, M_PI, 0, 0.0, 1e-12, 1e-14, NULL, 0, NULL, &o,
                                     NULL, NULL, NULL, &info);
    print_case("resonance", status, info.residual);
    ss_model_free(res);
    return 0;
}
