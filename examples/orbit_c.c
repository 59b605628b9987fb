/* The stick-slip cycle of the belt from C (ss_periodic_orbit): a mass m = 1 kg on a spring
 * k = 4 N/m to the wall, on a belt at v_b = 0.3 m/s with set-valued Coulomb friction (mu_s =
 * 0.4, mu_k = 0.3) under event_driven. The cycle is autonomous: its period is an unknown. The
 * program checks the period against the closed form (pi + 2 asin(v_b/(A w)))/w + 2 (mu_s -
 * mu_k) m g/(k v_b), with w = sqrt(k/m) and A = hypot((mu_s - mu_k) m g/k, v_b/w), and exits
 * with 1 when it is off by more than 1e-8 relative or the solver failed. */
#include <math.h>
#include <stdio.h>
#include <stickslip.h>

int main(void) {
    const double params[] = {1.0, 4.0, 0.3, 9.81, 0.4, 0.3};     /* m, k, v_b, g, mu_s, mu_k */
    double y[2] = {0.8, 0.3};          /* the guess: stuck on the belt (v = v_b) at x = 0.8 m */
    double re[2], im[2], rtol = 1e-12, atol = 1e-14;
    ss_orbit_info info;
    int status = ss_periodic_orbit(SS_SCENE_BELT, SS_LAW_COULOMB, SS_METHOD_EVENT_DRIVEN,
                                   "m,k,v_b,g,mu_s,mu_k", 6, params, 2, y, 3.3, 1, 1, &rtol, &atol,
                                   "", 0, NULL, NULL, NULL, re, im, &info);
    if (status != SS_OK) {
        char msg[256];
        ss_message(status, msg, sizeof msg);
        printf("ss_periodic_orbit: %s (status %d, residual %.3g)\n", msg, status, info.residual);
        return 1;
    }
    printf("period %.12f s after %d Newton iterations (%d runs), residual %.2g\n", info.period,
           info.iterations, info.runs, info.residual);
    printf("multipliers %.6f and %.6f (the trivial one: %d)\n", re[0], re[1], info.trivial);

    /* The closed forms. */
    double w = sqrt(4.0 / 1.0), A = hypot(0.1 * 9.81 / 4.0, 0.3 / w);
    double period = (M_PI + 2.0 * asin(0.3 / (A * w))) / w + 2.0 * 0.1 * 9.81 / (4.0 * 0.3);
    printf("closed form %.12f s\n", period);
    return fabs(info.period - period) <= 1e-8 * period ? 0 : 1;
}
