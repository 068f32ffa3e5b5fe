/* Every observable, listed once (docs/architecture.md, "How to add an observable"): X(NAME) for a
 * `const gr_observable_type gr_obs_NAME` defined in src/analysis/obs_NAME.c. The registry
 * (gr_observables, src/analysis/observe.c) is generated from this list; its order is the order
 * of `granule observables`, `granule keys` and the [analysis] keys in a run's scene.ini, so a new
 * observable goes at the end (one new line above the closing comment). */
#ifndef GR_OBS_LIST_H
#define GR_OBS_LIST_H

#define GR_OBSERVABLE_LIST(X)                                                                      \
    X(moments)                                                                                     \
    X(freepath)                                                                                    \
    X(postcollision)                                                                               \
    X(gaps)                                                                                        \
    X(sk)                                                                                          \
    X(pair)                                                                                        \
    X(pv)                                                                                          \
    X(msd)                                                                                         \
    X(vacf)                                                                                        \
    X(vcorr)                                                                                       \
    X(clusters)                                                                                    \
    X(pressure)                                                                                    \
    X(collisions)                                                                                  \
    X(profile)                                                                                     \
    X(species)                                                                                     \
    /* a new observable: X(NAME) \ on the line above this one */

#endif
