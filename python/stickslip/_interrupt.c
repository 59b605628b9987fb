/* Ctrl-C during a long Fortran call of the extension: while a call runs, SIGINT sets the
 * caller's stop flag (which the integrators look at every 4096 steps) instead of waiting for
 * the interpreter, which cannot run its own handler until the call returns. The previous
 * handler (Python's) is put back when the call ends; the facade then raises
 * KeyboardInterrupt. Also the clocks that time a call (stats["cpu_seconds"]).
 * Called from the f2py layer (_wrap.f90) through bind(C). */
#include <signal.h>
#include <stddef.h>
#include <time.h>

#if defined(CLOCK_PROCESS_CPUTIME_ID) && defined(CLOCK_MONOTONIC)
/* Clock `id` in seconds, clock() where it cannot be read. */
static double seconds_of(clockid_t id) {
    struct timespec ts;
    if (clock_gettime(id, &ts) == 0) return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
    return (double)clock() / CLOCKS_PER_SEC;
}
#define SS_CPU_CLOCK() seconds_of(CLOCK_PROCESS_CPUTIME_ID)
#define SS_WALL_CLOCK() seconds_of(CLOCK_MONOTONIC)
#else
#define SS_CPU_CLOCK() ((double)clock() / CLOCKS_PER_SEC)
#define SS_WALL_CLOCK() ((double)clock() / CLOCKS_PER_SEC)
#endif

/* The process's CPU time [s]: the clock of Python's time.process_time (clock() where there is
 * no CLOCK_PROCESS_CPUTIME_ID). */
double ss_py_cpu_seconds(void) { return SS_CPU_CLOCK(); }

/* A monotonic wall clock [s] for the calls too short to be worth two reads of the CPU clock,
 * which are system calls of a microsecond or more each (CLOCK_MONOTONIC is read without
 * one on Linux; clock() where it is missing). */
double ss_py_wall_seconds(void) { return SS_WALL_CLOCK(); }

static volatile int *stop_flag = NULL;

#if defined(_POSIX_C_SOURCE) || defined(__unix__) || defined(__APPLE__)
static struct sigaction previous;

static void on_sigint(int sig) {
    (void)sig;
    if (stop_flag != NULL) *stop_flag = 1;
}

void ss_py_arm(int *flag) {
    struct sigaction sa;
    stop_flag = flag;
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;
    sigaction(SIGINT, &sa, &previous);
}

void ss_py_disarm(void) {
    sigaction(SIGINT, &previous, NULL);
    stop_flag = NULL;
}
#else
void ss_py_arm(int *flag) { (void)flag; }   /* no POSIX signals: Ctrl-C waits for the call */
void ss_py_disarm(void) {}
#endif
