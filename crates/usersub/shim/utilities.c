/*
 * The Adams utility routines a user subroutine calls back into (SYSFNC, SYSARY, TIMGET,
 * ERRMES, USRMES; STEP, POLY, IMPACT, BISTOP, AKISPL, CUBSPL), in both conventions Adams accepts, forwarding to the functions linkage
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
    void (*utility)(const char *name, const double *args, int nargs, int nvars, int iord,
                    double *out, int *errflg);
    void (*gtaray)(int id, double *array, int *number, int *istat);
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

/*
 * Function utility routines: NAME(args) of the expression language, the first nvars
 * arguments its variables; IORD 0 the value, 1 the first partials, 2 the second (see
 * src/utilities.rs). VALUE/VECTOR/ARRAY receive 1, nvars or 3 numbers.
 */
static void utility(const char *name, const double *args, int nargs, int nvars, int iord,
                    double *out, int *errflg)
{
    double tmp[3] = {0.0, 0.0, 0.0};
    int n = iord == 0 ? 1 : (iord == 1 ? nvars : (nvars == 1 ? 1 : 3));
    if (!cb.utility) { *errflg = 1; out[0] = 0.0; return; }
    cb.utility(name, args, nargs, nvars, iord, tmp, errflg);
    for (int k = 0; k < n; k++) out[k] = tmp[k];
}

/* STEP(X, X0, H0, X1, H1, IORD, VALUE, ERRFLG) */
void step_(const double *x, const double *x0, const double *h0, const double *x1,
           const double *h1, const int *iord, double *value, int *errflg)
{
    double a[5] = {*x, *x0, *h0, *x1, *h1};
    utility("STEP", a, 5, 1, *iord, value, errflg);
}

/* POLY(X, X0, PAR, NPAR, IORD, VALUE, ERRFLG): PAR(1) + PAR(2)(X − X0) + … */
void poly_(const double *x, const double *x0, const double *par, const int *npar,
           const int *iord, double *value, int *errflg)
{
    double a[32];
    int n = *npar < 30 ? *npar : 30;
    if (*npar > 30 || *npar < 1) { *errflg = 1; *value = 0.0; return; }
    a[0] = *x;
    a[1] = *x0;
    for (int k = 0; k < n; k++) a[2 + k] = par[k];
    utility("POLY", a, 2 + n, 1, *iord, value, errflg);
}

/* IMPACT(X, XD, X1, K, E, CMAX, D, IORD, VECTOR, ERRFLG) */
void impact_(const double *x, const double *xd, const double *x1, const double *k,
             const double *e, const double *cmax, const double *d, const int *iord,
             double *vector, int *errflg)
{
    double a[7] = {*x, *xd, *x1, *k, *e, *cmax, *d};
    utility("IMPACT", a, 7, 2, *iord, vector, errflg);
}

/* BISTOP(X, XD, X1, X2, K, E, CMAX, D, IORD, VECTOR, ERRFLG) */
void bistop_(const double *x, const double *xd, const double *x1, const double *x2,
             const double *k, const double *e, const double *cmax, const double *d,
             const int *iord, double *vector, int *errflg)
{
    double a[8] = {*x, *xd, *x1, *x2, *k, *e, *cmax, *d};
    utility("BISTOP", a, 8, 2, *iord, vector, errflg);
}

/* AKISPL(XVAL, ZVAL, ID, IORD, ARRAY, ERRFLG) and CUBSPL(…): SPLINE/ID at (x, z). */
void akispl_(const double *xval, const double *zval, const int *id, const int *iord,
             double *array, int *errflg)
{
    double a[3] = {*xval, *zval, (double)*id};
    utility("AKISPL", a, 3, 2, *iord, array, errflg);
}

void cubspl_(const double *xval, const double *zval, const int *id, const int *iord,
             double *array, int *errflg)
{
    double a[3] = {*xval, *zval, (double)*id};
    utility("CUBSPL", a, 3, 2, *iord, array, errflg);
}

/* C style: scalars by value. */
void c_step(double x, double x0, double h0, double x1, double h1, int iord, double *value,
            int *errflg)
{
    step_(&x, &x0, &h0, &x1, &h1, &iord, value, errflg);
}

void c_poly(double x, double x0, const double *par, int npar, int iord, double *value,
            int *errflg)
{
    poly_(&x, &x0, par, &npar, &iord, value, errflg);
}

void c_impact(double x, double xd, double x1, double k, double e, double cmax, double d,
              int iord, double *vector, int *errflg)
{
    impact_(&x, &xd, &x1, &k, &e, &cmax, &d, &iord, vector, errflg);
}

void c_bistop(double x, double xd, double x1, double x2, double k, double e, double cmax,
              double d, int iord, double *vector, int *errflg)
{
    bistop_(&x, &xd, &x1, &x2, &k, &e, &cmax, &d, &iord, vector, errflg);
}

void c_akispl(double xval, double zval, int id, int iord, double *array, int *errflg)
{
    akispl_(&xval, &zval, &id, &iord, array, errflg);
}

void c_cubspl(double xval, double zval, int id, int iord, double *array, int *errflg)
{
    cubspl_(&xval, &zval, &id, &iord, array, errflg);
}

/* GTARAY(ID, ARRAY, NUMBER, ISTAT): the values of ARRAY/ID. */
void gtaray_(const int *id, double *array, int *number, int *istat)
{
    if (!cb.gtaray) { *number = 0; *istat = 1; return; }
    cb.gtaray(*id, array, number, istat);
}

void c_gtaray(int id, double *array, int *number, int *istat)
{
    gtaray_(&id, array, number, istat);
}
