/* A C-style SFOSUB (Adams' C interface: mixed-case name, the statement's struct first): a
 * contact force in the style of Adams' IMPACT between markers PAR[5] and PAR[6],
 * PAR = x1, k, e, cmax, d, i, j. */
#include <math.h>

struct sAdamsSforce {
    int ID;
    int NPAR;
    const double *PAR;
};

void c_sysfnc(const char *fncnam, int *ipar, int nsize, double *states, int *errflg);

static double step(double x, double x0, double h0, double x1, double h1)
{
    if (x <= x0) return h0;
    if (x >= x1) return h1;
    double s = (x - x0) / (x1 - x0);
    return h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s);
}

void Sfosub(const struct sAdamsSforce *sforce, double time, int dflag, int iflag,
            double *result)
{
    const double *p = sforce->PAR;
    int ipar[2] = {(int)p[5], (int)p[6]};
    int err = 0;
    double x, v;
    c_sysfnc("DM", ipar, 2, &x, &err);
    c_sysfnc("VR", ipar, 2, &v, &err);
    double x1 = p[0], k = p[1], e = p[2], cmax = p[3], d = p[4];
    double f = 0.0;
    if (x < x1) {
        f = k * pow(x1 - x, e) - step(x, x1 - d, cmax, x1, 0.0) * v;
        if (f < 0.0) f = 0.0;
    }
    *result = f;
}
