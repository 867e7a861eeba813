/*
 * The Adams utility routines a user subroutine calls back into (SYSFNC, SYSARY, TIMGET,
 * ERRMES, USRMES), in both conventions Adams accepts, forwarding to the functions linkage
 * installs with linkage_usersub_install. Loaded with RTLD_GLOBAL before any user library,
 * so that the user library's undefined references (sysfnc_, c_sysfnc, ...) resolve here.
 *
 * Fortran (gfortran, Intel Fortran on Linux): lower-case names with a trailing underscore,
 * every argument by reference, LOGICAL as a 4-byte integer, the length of each CHARACTER
 * argument passed by value (size_t) after all the others, in order.
 */
#include <stddef.h>
#include <string.h>

struct linkage_callbacks {
    void (*sysfnc)(const char *name, size_t name_len, const int *ipar, int nsize,
                   double *states, int *errflg);
    void (*sysary)(const char *name, size_t name_len, const int *ipar, int nsize,
                   double *states, int *nstates, int *errflg);
    void (*timget)(double *time);
    void (*errmes)(int errflg, const char *msg, size_t msg_len, int id, const char *end,
                   size_t end_len);
    void (*usrmes)(int msgflg, const char *msg, size_t msg_len, int id, const char *type,
                   size_t type_len);
};

static struct linkage_callbacks cb;

void linkage_usersub_install(const struct linkage_callbacks *c) { cb = *c; }

/* Fortran style */
void sysfnc_(const char *fncnam, const int *ipar, const int *nsize, double *states,
             int *errflg, size_t fncnam_len)
{
    if (!cb.sysfnc) { *errflg = 1; return; }
    cb.sysfnc(fncnam, fncnam_len, ipar, *nsize, states, errflg);
}

void sysary_(const char *fncnam, const int *ipar, const int *nsize, double *states,
             int *nstates, int *errflg, size_t fncnam_len)
{
    if (!cb.sysary) { *errflg = 1; *nstates = 0; return; }
    cb.sysary(fncnam, fncnam_len, ipar, *nsize, states, nstates, errflg);
}

void timget_(double *time)
{
    if (cb.timget) cb.timget(time);
}

void errmes_(const int *errflg, const char *mesage, const int *id, const char *endflg,
             size_t mesage_len, size_t endflg_len)
{
    if (cb.errmes) cb.errmes(*errflg, mesage, mesage_len, *id, endflg, endflg_len);
}

void usrmes_(const int *msgflg, const char *mesage, const int *id, const char *msgtyp,
             size_t mesage_len, size_t msgtyp_len)
{
    if (cb.usrmes) cb.usrmes(*msgflg, mesage, mesage_len, *id, msgtyp, msgtyp_len);
}

/* C style (Adams' c_ utility names; strings NUL-terminated, scalars by value) */
void c_sysfnc(const char *fncnam, int *ipar, int nsize, double *states, int *errflg)
{
    sysfnc_(fncnam, ipar, &nsize, states, errflg, strlen(fncnam));
}

void c_sysary(const char *fncnam, int *ipar, int nsize, double *states, int *nstates,
              int *errflg)
{
    sysary_(fncnam, ipar, &nsize, states, nstates, errflg, strlen(fncnam));
}

void c_timget(double *time) { timget_(time); }

void c_errmes(int errflg, const char *mesage, int id, const char *endflg)
{
    errmes_(&errflg, mesage, &id, endflg, strlen(mesage), strlen(endflg));
}

void c_usrmes(int msgflg, const char *mesage, int id, const char *msgtyp)
{
    usrmes_(&msgflg, mesage, &id, msgtyp, strlen(mesage), strlen(msgtyp));
}
