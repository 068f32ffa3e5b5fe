/* The registry of collision models, generated from models/list.h: every model's descriptor and
 * prepare are compiled here (GR_MODEL_IMPL), in the order of the lists (normal laws, tangential
 * laws, event rules). */
#include "models/list.h" /* the models' declarations and the layout of their own parameters */
#define GR_MODEL_IMPL
#include "models/list.h" /* again: now each model's descriptor, prepare, ... (GR_MODEL_IMPL) */

/* every tangential law gives the CVODE reference its force (models/reference.h): a law listed in
 * GR_TANGENTIAL_MODELS without a `static const gr_reference_law NAME_reference` does not build */
#define GR_REFERENCE_CHECK(A, NAME)                                                                \
    _Static_assert(sizeof(NAME##_reference) == sizeof(gr_reference_law),                           \
                   #NAME ": no reference force");
GR_TANGENTIAL_MODELS(GR_REFERENCE_CHECK, )
/* and every rolling law its torque */
#define GR_REFERENCE_ROLLING_CHECK(A, NAME)                                                        \
    _Static_assert(sizeof(NAME##_reference) == sizeof(gr_reference_rolling),                       \
                   #NAME ": no reference torque");
GR_ROLLING_MODELS(GR_REFERENCE_ROLLING_CHECK, )

#define GR_REGISTRY_ENTRY(A, NAME) &gr_model_##NAME,
const gr_model *const gr_models[] = {
    GR_NORMAL_MODELS(GR_REGISTRY_ENTRY, ) GR_TANGENTIAL_MODELS(GR_REGISTRY_ENTRY, )
        GR_EVENT_MODELS(GR_REGISTRY_ENTRY, ) GR_ROLLING_MODELS(GR_REGISTRY_ENTRY, ) NULL,
};
