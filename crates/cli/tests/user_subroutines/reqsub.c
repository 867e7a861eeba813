/* A C-style REQSUB (Adams' C interface: `Reqsub`, the request's struct first): the same eight
 * outputs as the Fortran reqsub in spring.f90, read with c_sysfnc and c_timget. */

struct sAdamsRequest {
    int ID;
    int NPAR;
    const double *PAR;
};

void c_sysfnc(const char *fncnam, int *ipar, int nsize, double *states, int *errflg);
void c_timget(double *time);

void Reqsub(const struct sAdamsRequest *req, double time, int iflag, double *result)
{
    const double *p = req->PAR;
    int ipar[4] = {(int)p[0], (int)p[1], 0, 0};
    int err = 0;
    c_timget(&result[0]);
    c_sysfnc("DZ", ipar, 2, &result[1], &err);
    c_sysfnc("VZ", ipar, 4, &result[2], &err);
    c_sysfnc("ACCZ", ipar, 4, &result[3], &err);
    c_sysfnc("DM", ipar, 2, &result[4], &err);
    c_sysfnc("VR", ipar, 2, &result[5], &err);
    result[6] = p[2] * result[1];
    int force[4] = {(int)p[3], 0, 4, 0};
    c_sysfnc("SFORCE", force, 4, &result[7], &err);
}

/* A C-style REQSUB that counts the calls with IFLAG set: every value is that count. */
static int iflag_calls = 0;

void Iflags(const struct sAdamsRequest *req, double time, int iflag, double *result)
{
    (void)req;
    (void)time;
    if (iflag) iflag_calls++;
    for (int k = 0; k < 8; k++) result[k] = (double)iflag_calls;
}
