#include <stdio.h>
#include <math.h>
#include <gsl/gsl_errno.h>
#include "granule/fokker_planck.h"
#include "granule/analysis.h"
int main(void){ gsl_set_error_handler_off(); gr_fp_settings s; gr_fp_settings_default(&s); gr_fp_quad *q; gr_error e={0}; gr_fp_quad_alloc(&s,&q,&e);
 double ranges[][2]={{1,3},{1.5,4},{2,4.5},{3,6},{5,10}};
 for(int r=0;r<5;r++){ double x[200],y[200],sg[200]; int n=0; for(int k=0;k<60;k++){double v=ranges[r][0]+(ranges[r][1]-ranges[r][0])*k/59.0; double p; gr_fp_Q_pdf(q,v,&p,NULL,&e); x[n]=v;y[n]=p;sg[n]=0.01*p;n++;}
  gr_fit f; double p0[3]={1,1,2}; int rc=gr_fit_stretched_exp(x,y,sg,n,p0,&f,&e); printf("range [%g,%g]: rc %d A %.4g v0 %.4g beta %.4f (1/v0^beta = %.4f)\n",ranges[r][0],ranges[r][1],rc,f.p[0],f.p[1],f.p[2],pow(f.p[1],-f.p[2]));}
}
