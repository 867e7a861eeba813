/* A C-style GFOSUB standing in for the OMTLMSimulator shaft's co-simulation force: a linear
 * stiffness on the displacement of marker PAR[0] from PAR[1] in PAR[2]'s axes,
 * F = -k·[DX, DY, DZ], no torque (k = 1 N/mm). */
struct sAdamsGforce {
    int ID;
    int NPAR;
    const double *PAR;
};

void c_sysary(const char *fncnam, int *ipar, int nsize, double *states, int *nstates,
              int *errflg);
void c_errmes(int errflg, const char *mesage, int id, const char *endflg);

void Gfosub(const struct sAdamsGforce *gforce, double time, int dflag, int iflag,
            double *result)
{
    int ipar[3] = {(int)gforce->PAR[0], (int)gforce->PAR[1], (int)gforce->PAR[2]};
    double d[3];
    int n = 0, err = 0;
    c_sysary("TDISP", ipar, 3, d, &n, &err);
    c_errmes(err, "TDISP cannot be read", gforce->ID, "STOP");
    for (int k = 0; k < 3; k++) {
        result[k] = -1.0 * d[k];
        result[3 + k] = 0.0;
    }
}
