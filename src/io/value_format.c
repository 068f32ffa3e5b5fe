/* "value +- error" as every table and plot label prints it (declared in granule/compare.h, the
 * comparison's public header, where users meet it; defined here, below the plots that use it). */
#include <math.h>
#include <stdio.h>

#include "granule/compare.h"

void gr_compare_format(double value, double error, char *buf, size_t size)
{
    if (!isfinite(value)) {
        snprintf(buf, size, "n/a");
        return;
    }
    if (!isfinite(error) || !(error > 0.0)) {
        snprintf(buf, size, "%.4g", value);
        return;
    }
    const int last = (int)floor(log10(error)) - 1; /* decimal place of the error's second digit */
    const int lead = (int)floor(log10(fmax(fabs(value), error)));
    if (lead >= -3 && lead < 5) {
        const int dec = last < 0 ? -last : 0;
        snprintf(buf, size, "%.*f +- %.*f", dec, value, dec, error);
    } else { /* a common power of ten */
        const double scale = pow(10.0, lead);
        const int dec = lead - last > 0 ? lead - last : 0;
        snprintf(buf, size, "(%.*f +- %.*f)e%+03d", dec, value / scale, dec, error / scale, lead);
    }
}
