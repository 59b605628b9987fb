/* Your own system from C (the ss_model_* functions of stickslip.h): a dry clutch.
 *
 * Two shafts: a flywheel of inertia J1 = 1 kg m^2 spinning at w0 = 10 rad/s and a drum of
 * inertia J2 = 2 kg m^2 at rest, joined by a Coulomb clutch (mu_s 0.5, mu_k 0.4, friction
 * radius 1 m) whose normal force of 50 N is applied at t_on = 0.1 s (the product of a constant
 * and a step signal). While the clutch slips its torque T = mu_k N = 20 N m slows the
 * flywheel and speeds up the drum: the slip w1 - w2 falls at T (1/J1 + 1/J2) = 30 rad/s^2, so
 * the clutch locks at t_lock = t_on + w0 / 30 = 0.4333 s, and then both turn at the common
 * speed J1 w0 / (J1 + J2) = 10/3 rad/s (angular momentum is conserved; nothing loads the
 * clutch after it locks). The event-driven method runs it to 1 s; the program checks the
 * lock time, the one event and the angles and speeds at 1 s against these closed forms, and
 * exits with status 1 when any is off by more than 1e-9.
 *
 * Build against an installed stickslip:
 *     cc model_c.c $(pkg-config --cflags --libs stickslip)
 * (meson test builds and runs it in-tree.) Prints key=value lines.
 */
#include <math.h>
#include <stdio.h>
#include <stickslip.h>

/* Print the model's last error (it names the element) and return 1. */
static int fail(const ss_model *m, const char *what, int status) {
    char msg[512];
    ss_model_message(m, msg, sizeof msg);
    fprintf(stderr, "%s failed (status %d): %s\n", what, status, msg);
    return 1;
}

int main(void) {
    const double J1 = 1.0, J2 = 2.0, w0 = 10.0, mu_s = 0.5, mu_k = 0.4, N = 50.0, t_on = 0.1,
                 t_end = 1.0;
    ss_model *m = ss_model_new();
    if (m == NULL) return 1;

    int flywheel = ss_model_add_body(m, J1, 0.0, w0); /* angle [rad], speed [rad/s] */
    int drum = ss_model_add_body(m, J2, 0.0, 0.0);
    int normal = ss_signal_mul(m, ss_signal_constant(m, N), ss_signal_step(m, t_on, 0.0, 1.0));
    const double law_values[] = {mu_s, mu_k};
    int clutch = ss_model_add_contact(m, flywheel, drum, SS_LAW_COULOMB, normal, SS_NO_SIGNAL, "mu_s,mu_k", 2,
                                      law_values);
    if (flywheel < 0 || drum < 0 || normal < 0 || clutch < 0) return fail(m, "building the model", -1);

    enum { NOUT = 11, NB = 2, ROOM = 8 };
    double t[NOUT], x[NB * NOUT], v[NB * NOUT], events[4 * ROOM];
    int64_t n_events = 0;
    ss_stats st;
    for (int i = 0; i < NOUT; i++) t[i] = t_end * i / (NOUT - 1);
    int status = ss_model_simulate(m, SS_METHOD_EVENT_DRIVEN, t_end, 0.0, 1e-12, 1e-14, NULL, 0, NULL, NOUT, t,
                                   x, v, &st, ROOM, events, &n_events);
    if (status != SS_OK) return fail(m, "ss_model_simulate", status);

    /* The closed forms. */
    double T = mu_k * N, t_lock = t_on + w0 / (T * (1.0 / J1 + 1.0 / J2)), w_c = J1 * w0 / (J1 + J2);
    double slip_time = t_lock - t_on;
    double x1 = w0 * t_lock - 0.5 * T / J1 * slip_time * slip_time + w_c * (t_end - t_lock);
    double x2 = 0.5 * T / J2 * slip_time * slip_time + w_c * (t_end - t_lock);
    const int last = NOUT - 1;
    double err[] = {fabs(events[0] - t_lock), fabs(x[0 * NOUT + last] - x1), fabs(x[1 * NOUT + last] - x2),
                    fabs(v[0 * NOUT + last] - w_c), fabs(v[1 * NOUT + last] - w_c)};
    printf("n_events=%lld\nevent_kind=%g\nevent_contact=%g\n", (long long)n_events, events[1], events[3]);
    printf("t_lock=%.15g\nt_lock_exact=%.15g\n", events[0], t_lock);
    printf("flywheel_angle=%.15g\nflywheel_angle_exact=%.15g\n", x[0 * NOUT + last], x1);
    printf("drum_angle=%.15g\ndrum_angle_exact=%.15g\n", x[1 * NOUT + last], x2);
    printf("speeds=%.15g,%.15g\nspeed_exact=%.15g\nnfev=%lld\n", v[0 * NOUT + last], v[1 * NOUT + last], w_c,
           (long long)st.nfev);
    int ok = n_events == 1 && events[1] == SS_EVENT_STICK && events[3] == clutch;
    for (int k = 0; k < 5; k++) ok = ok && err[k] < 1e-9;

    /* A bad element comes back as a status, and the message names the element: a spring to a
     * third body the model does not have. */
    char msg[512];
    ss_model_add_spring(m, drum, 3, 100.0, 0.0);
    int bad = ss_model_check(m);
    ss_model_message(m, msg, sizeof msg);
    printf("bad_status=%d\nbad_message=%s\n", bad, msg);
    ok = ok && bad == SS_BAD_BODY;

    ss_model_free(m);
    printf("ok=%d\n", ok);
    return ok ? 0 : 1;
}
