/* Cases of the model C API (ss_model_*) for tests/fortran/test_stickslip_capi.py, which builds the same
 * models with stickslip.Model and compares, and checks the status of every bad input.
 *
 * Prints one record per line, fields separated by blanks:
 *   row RUN i t x_1 .. x_nb v_1 .. v_nb     the output of a run
 *   event RUN k t kind position contact     its events
 *   stats RUN status n_written nfev n_events
 *   drive RUN i f_1 .. f_nd                 the drives' forces of a run
 *   case NAME status elem_kind elem_index | message
 */
#include <stdio.h>
#include <stdlib.h>
#include <stickslip.h>

enum { ROOM = 64, STEPS = 20000 };

/* n rows of x and v written, of n_out (the row stride of x and v). */
static void print_run(const char *name, int nb, int n, int n_out, const double *t, const double *x,
                      const double *v, const ss_stats *st, const double *events, int64_t n_events) {
    printf("stats %s %d %d %lld %lld\n", name, st->status, st->n_written, (long long)st->nfev,
           (long long)n_events);
    for (int i = 0; i < n; i++) {
        printf("row %s %d %.17g", name, i, t[i]);
        for (int j = 0; j < nb; j++) printf(" %.17g", x[j * n_out + i]);
        for (int j = 0; j < nb; j++) printf(" %.17g", v[j * n_out + i]);
        printf("\n");
    }
    for (int64_t k = 0; k < n_events && k < ROOM; k++)
        printf("event %s %lld %.17g %.17g %.17g %.17g\n", name, (long long)k, events[4 * k], events[4 * k + 1],
               events[4 * k + 2], events[4 * k + 3]);
}

/* A status, the element the model names, and the model's message. */
static void print_case(const char *name, int status, const ss_model *m) {
    int kind = -1, index = -1;
    char msg[512] = "";
    ss_model_error(m, &kind, &index);
    ss_model_message(m, msg, sizeof msg);
    printf("case %s %d %d %d | %s\n", name, status, kind, index, msg);
}

/* Model A: two bodies, springs, a damper, forces of every kind of signal, a LuGre contact
 * between the bodies and a Stribeck contact on a surface whose speed is a sine. */
static ss_model *model_a(void) {
    ss_model *m = ss_model_new();
    int b1 = ss_model_add_body(m, 1.5, 0.02, 0.3);
    int b2 = ss_model_add_body(m, 0.8, -0.01, 0.0);
    ss_model_add_spring(m, b1, SS_GROUND, 120.0, 0.05);
    ss_model_add_spring(m, b1, b2, 60.0, 0.0);
    ss_model_add_damper(m, b2, SS_GROUND, 0.7);
    ss_model_add_force(m, b1, ss_signal_add(m, ss_signal_sine(m, 3.0, 2.0, 0.3, 0.5), ss_signal_ramp(m, 0.2, 0.3, 4.0)));
    const double tt[] = {0.0, 0.3, 0.6, 1.0}, tv[] = {0.0, 2.0, -1.0, 0.5};
    ss_model_add_force(m, b2, ss_signal_sub(m, ss_signal_table(m, 4, tt, tv), ss_signal_constant(m, 0.25)));
    const double lugre[] = {0.5, 0.4, 0.02};
    ss_model_add_contact(m, b1, b2, ss_code("law", "lugre"), ss_signal_constant(m, 15.0), SS_NO_SIGNAL,
                         "mu_s, mu_k, v_s", 3, lugre);
    const double stribeck[] = {0.6, 0.45, 0.05};
    int normal = ss_signal_mul(m, ss_signal_step(m, 0.3, 10.0, 20.0), ss_signal_constant(m, 1.0));
    ss_model_add_contact(m, b2, SS_GROUND, SS_LAW_STRIBECK, normal, ss_signal_sine(m, 0.5, 1.0, 0.0, 1.0),
                         "mu_s,mu_k,v_s", 3, stribeck);
    return m;
}

/* Model B: the example (a Coulomb clutch engaging at 0.4 s, a Stribeck contact on a
 * belt at 1.5 m/s), for event_driven. */
static ss_model *model_b(void) {
    ss_model *m = ss_model_new();
    int j1 = ss_model_add_body(m, 1.0, 0.0, 10.0);
    int j2 = ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_spring(m, j1, SS_GROUND, 100.0, 0.0);
    ss_model_add_damper(m, j1, j2, 2.0);
    ss_model_add_force(m, j1, ss_signal_sine(m, 10.0, 5.0, 0.0, 0.0));
    const double coulomb[] = {0.55, 0.5};
    ss_model_add_contact(m, j1, j2, SS_LAW_COULOMB,
                         ss_signal_mul(m, ss_signal_constant(m, 20.0), ss_signal_step(m, 0.4, 0.0, 1.0)),
                         SS_NO_SIGNAL, "mu_s,mu_k", 2, coulomb);
    ss_model_add_contact(m, j2, SS_GROUND, SS_LAW_STRIBECK, ss_signal_constant(m, 98.1),
                         ss_signal_constant(m, 1.5), NULL, 0, NULL);
    return m;
}

/* Model C: a drill string, its top (body 1) driven at 5 rad/s through a torsional spring to
 * the bit (body 2), which has Stribeck friction on the bottom. */
static ss_model *model_c(void) {
    ss_model *m = ss_model_new();
    int top = ss_model_add_body(m, 50.0, 0.0, 0.0);
    int bit = ss_model_add_body(m, 374.0, 0.0, 0.0);
    ss_model_add_spring(m, top, bit, 473.0, 0.0);
    const double stribeck[] = {0.8, 0.5};
    ss_model_add_contact(m, bit, SS_GROUND, SS_LAW_STRIBECK, ss_signal_constant(m, 1000.0), SS_NO_SIGNAL,
                         "mu_s,mu_k", 2, stribeck);
    ss_model_add_drive(m, top, SS_DRIVE_VELOCITY, ss_signal_constant(m, 5.0));
    return m;
}

static void run(const char *name, ss_model *m, int method, double t_end, double h, double rtol, double atol,
                const char *ckeys, int nc, const double *cvals, int n) {
    double *t = calloc((size_t)n, sizeof *t), *x = calloc(2 * (size_t)n, sizeof *x);
    double *v = calloc(2 * (size_t)n, sizeof *v), events[4 * ROOM];
    int64_t n_events = -1;
    ss_stats st;
    for (int i = 0; i < n; i++) t[i] = n > 1 ? t_end * i / (n - 1) : t_end;
    ss_model_simulate(m, method, t_end, h, rtol, atol, ckeys, nc, cvals, n, t, x, v, &st, ROOM, events, &n_events);
    print_run(name, 2, st.n_written, n, t, x, v, &st, events, n_events);
    double force[ROOM];
    if (n <= ROOM && ss_model_drive_forces(m, n, force) == SS_OK)     /* one drive at most here */
        for (int i = 0; i < n; i++) printf("drive %s %d %.17g\n", name, i, force[i]);
    free(t);
    free(x);
    free(v);
}

int main(void) {
    ss_model *a = model_a(), *b = model_b(), *c = model_c();
    const double every[] = {1.0}, steps[] = {1e-6, 0.05};
    run("a_dopri5", a, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-9, 1e-11, "hmin,hmax", 2, steps, 21);
    run("a_rk4", a, SS_METHOD_RK4, 1.0, 2e-5, 0.0, 0.0, "", 0, NULL, 21);
    run("a_dopri5_every", a, SS_METHOD_DOPRI5, 0.5, 0.0, 1e-6, 1e-8, "every_step", 1, every, STEPS);
    run("b_event_driven", b, SS_METHOD_EVENT_DRIVEN, 1.5, 0.0, 1e-10, 1e-12, NULL, 0, NULL, 301);
    run("c_drive_dopri5", c, SS_METHOD_DOPRI5, 4.0, 0.0, 1e-9, 1e-11, "hmin", 1, steps, 41);
    run("c_drive_event_driven", c, SS_METHOD_EVENT_DRIVEN, 10.0, 0.0, 1e-10, 1e-12, NULL, 0, NULL, 41);
    ss_model_free(c);

    /* Bad handles: NULL and a pointer to something else, for every function. */
    double fake[64] = {0.0}, t[2] = {0.0, 1.0}, x[4], v[4], one = 1.0;
    ss_model *handles[] = {NULL, (ss_model *)fake};
    const char *hnames[] = {"null", "fake"};
    char line[64];
    for (int k = 0; k < 2; k++) {
        ss_model *h = handles[k];
        int statuses[] = {
            ss_model_add_body(h, 1.0, 0.0, 0.0), ss_model_add_spring(h, 1, 0, 1.0, 0.0),
            ss_model_add_damper(h, 1, 0, 1.0), ss_model_add_force(h, 1, 1),
            ss_model_add_contact(h, 1, 0, SS_LAW_COULOMB, 1, 0, NULL, 0, NULL), ss_signal_constant(h, 1.0),
            ss_signal_step(h, 1.0, 0.0, 1.0), ss_signal_ramp(h, 0.0, 1.0, 1.0), ss_signal_sine(h, 1.0, 1.0, 0.0, 0.0),
            ss_signal_table(h, 1, &one, &one), ss_signal_add(h, 1, 1), ss_signal_sub(h, 1, 1), ss_signal_mul(h, 1, 1),
            ss_model_check(h), ss_model_error(h, NULL, NULL),
            ss_model_simulate(h, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t, x, v, NULL, 0, NULL,
                              NULL),
            ss_model_add_drive(h, 1, SS_DRIVE_VELOCITY, 1), ss_model_drive_forces(h, 2, x)};
        for (size_t i = 0; i < sizeof statuses / sizeof statuses[0]; i++) {
            snprintf(line, sizeof line, "%s_handle_%zu", hnames[k], i);
            print_case(line, statuses[i], h);
        }
        ss_model_free(h);   /* nothing happens */
    }

    /* Bad elements, each in a model of its own: status, and the element ss_model_error names. */
    ss_model *m = ss_model_new();
    print_case("empty", ss_model_simulate(m, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t, x, v,
                                          NULL, 0, NULL, NULL), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_spring(m, 1, 2, 10.0, 0.0);
    print_case("spring_body", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_damper(m, 1, 1, 1.0);
    print_case("damper_self", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_drive(m, 5, SS_DRIVE_POSITION, ss_signal_constant(m, 1.0));
    print_case("drive_body", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_drive(m, 2, SS_DRIVE_POSITION, ss_signal_step(m, 1.0, 0.0, 1.0));
    print_case("drive_step", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_body(m, -2.0, 0.0, 0.0);
    print_case("negative_mass", ss_model_simulate(m, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t,
                                                  x, v, NULL, 0, NULL, NULL), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_spring(m, 1, 0, -5.0, 0.0);
    print_case("negative_k", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_damper(m, 1, 0, 1.0);
    ss_model_add_damper(m, 1, 0, -1.0);
    print_case("negative_c", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_force(m, 1, ss_signal_ramp(m, 0.0, 0.0, 1.0));
    print_case("ramp_duration", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_force(m, 1, ss_signal_constant(m, 1.0));
    ss_model_add_force(m, 1, 7);
    print_case("unknown_signal", ss_model_check(m), m);
    ss_model_free(m);

    const double mu[] = {0.5, 0.4};
    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_contact(m, 1, SS_GROUND, 999, ss_signal_constant(m, 1.0), SS_NO_SIGNAL, NULL, 0, NULL);
    print_case("unknown_law", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_contact(m, 1, 2, ss_code("law", "coulomb"), ss_signal_constant(m, 1.0), SS_NO_SIGNAL, NULL, 0,
                         NULL);
    ss_model_add_contact(m, 2, SS_GROUND, ss_code("law", "no_such_law"), 1, SS_NO_SIGNAL, NULL, 0, NULL);
    print_case("unnamed_law", ss_model_check(m), m);
    ss_model_free(m);

    const double bad_mu[] = {0.5, -0.4};
    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_contact(m, 1, SS_GROUND, SS_LAW_COULOMB, ss_signal_constant(m, 1.0), SS_NO_SIGNAL, "mu_s,mu_k", 2,
                         bad_mu);
    print_case("negative_mu_k", ss_model_check(m), m);
    ss_model_free(m);

    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 0.0);
    ss_model_add_contact(m, 1, SS_GROUND, SS_LAW_COULOMB, ss_signal_constant(m, 1.0), SS_NO_SIGNAL, "mu_s,nonsense",
                         2, mu);
    print_case("unknown_param", ss_model_check(m), m);
    print_case("keys_not_values", ss_model_add_contact(m, 1, 0, SS_LAW_COULOMB, 1, 0, "mu_s,mu_k", 1, mu), m);
    print_case("values_null", ss_model_add_contact(m, 1, 0, SS_LAW_COULOMB, 1, 0, "mu_s,mu_k", 2, NULL), m);
    print_case("table_negative_n", ss_signal_table(m, -1, t, t), m);
    print_case("table_null", ss_signal_table(m, 2, NULL, t), m);
    ss_model_free(m);

    /* Bad arguments of ss_model_simulate on a good model. */
    m = ss_model_new();
    ss_model_add_body(m, 1.0, 0.0, 1.0);
    ss_model_add_contact(m, 1, SS_GROUND, SS_LAW_LUGRE, ss_signal_constant(m, 9.81), SS_NO_SIGNAL, NULL, 0, NULL);
    double ev[4];
    print_case("x_null", ss_model_simulate(m, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t, NULL, v,
                                           NULL, 0, NULL, NULL), m);
    print_case("events_null", ss_model_simulate(m, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t, x,
                                                v, NULL, 1, NULL, NULL), m);
    print_case("n_out_0", ss_model_simulate(m, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 0, t, x, v,
                                            NULL, 1, ev, NULL), m);
    print_case("method_0", ss_model_simulate(m, 0, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t, x, v, NULL, 0, NULL,
                                             NULL), m);
    print_case("method_99", ss_model_simulate(m, 99, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t, x, v, NULL, 0, NULL,
                                              NULL), m);
    print_case("controls_not_values", ss_model_simulate(m, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, "hmax,hmin", 1,
                                                        every, 2, t, x, v, NULL, 0, NULL, NULL), m);
    print_case("control_of_another_method", ss_model_simulate(m, SS_METHOD_DOPRI5, 1.0, 0.0, 1e-6, 1e-9, "theta", 1,
                                                              every, 2, t, x, v, NULL, 0, NULL, NULL), m);
    print_case("rk4_h_0", ss_model_simulate(m, SS_METHOD_RK4, 1.0, 0.0, 0.0, 0.0, NULL, 0, NULL, 2, t, x, v, NULL, 0,
                                            NULL, NULL), m);
    print_case("event_driven_lugre", ss_model_simulate(m, SS_METHOD_EVENT_DRIVEN, 1.0, 0.0, 1e-6, 1e-9, NULL, 0,
                                                       NULL, 2, t, x, v, NULL, 0, NULL, NULL), m);
    print_case("t_end_negative", ss_model_simulate(m, SS_METHOD_DOPRI5, -1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t,
                                                   x, v, NULL, 0, NULL, NULL), m);
    print_case("good_after_bad", ss_model_simulate(m, SS_METHOD_RADAU5, 1.0, 0.0, 1e-6, 1e-9, NULL, 0, NULL, 2, t, x,
                                                   v, NULL, 0, NULL, NULL), m);
    ss_model_free(m);

    ss_model_free(a);
    ss_model_free(b);
    return 0;
}
