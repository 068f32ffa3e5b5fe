/* granule models: the registered collision models and their parameters; granule keys: every
 * scene key as Markdown (docs/scene-keys.md is its output). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/model.h"
#include "granule/scene.h"

int cmd_models(int argc, char **argv)
{
    bool markdown = argc > 1 && !strcmp(argv[1], "--markdown");
    if (argc > 1 && !markdown) {
        printf("usage: granule models [--markdown]\nLists every collision model, its kind and its parameters (unit, default, allowed range).\n");
        return strcmp(argv[1], "--help") && strcmp(argv[1], "-h") ? EXIT_REFUSED : EXIT_OK;
    }
    int w_name = 8, w_unit = 5; /* the columns of the plain listing fit every model's longest name and unit */
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            const int wn = (int)strlen(gr_models[m]->params[i].name), wu = (int)strlen(gr_models[m]->params[i].unit);
            w_name = wn > w_name ? wn : w_name;
            w_unit = wu > w_unit ? wu : w_unit;
        }
    }
    for (int m = 0; gr_models[m]; m++) {
        const gr_model *md = gr_models[m];
        const char *kind = md->kind == GR_MODEL_NORMAL ? "normal force law"
                           : md->kind == GR_MODEL_TANGENTIAL ? "tangential force law"
                           : md->kind == GR_MODEL_ROLLING    ? "rolling torque law"
                                                             : "event rule";
        printf(markdown ? "### `%s` (%s)\n\n%s\n\n" : "%s  [%s]\n  %s\n", md->name, kind, md->summary);
        if (markdown && md->n_params) {
            printf("| parameter | unit | default | allowed | meaning |\n|---|---|---|---|---|\n");
        }
        for (int i = 0; i < md->n_params; i++) {
            const gr_param *p = &md->params[i];
            char range[80], def[32];
            if (p->type == GR_PARAM_BOOL) {
                snprintf(range, sizeof range, "true/false");
                snprintf(def, sizeof def, "%s", p->def != 0.0 ? "true" : "false");
            } else {
                snprintf(range, sizeof range, "%c%g, %s%c", p->min_open ? '(' : '[', p->min,
                         isinf(p->max) ? "inf" : "", p->max_open ? ')' : ']');
                if (!isinf(p->max)) {
                    snprintf(range, sizeof range, "%c%g, %g%c", p->min_open ? '(' : '[', p->min, p->max, p->max_open ? ')' : ']');
                }
                snprintf(def, sizeof def, "%g", p->def);
            }
            if (markdown) {
                printf("| `%s` | %s | %s | %s | %s |\n", p->name, p->unit, def, range, p->doc);
            } else {
                printf("    %-*s %-*s default %-8s range %-12s %s\n", w_name, p->name, w_unit, p->unit, def, range, p->doc);
            }
        }
        printf("\n");
    }
    return EXIT_OK;
}

int cmd_keys(int argc, char **argv)
{
    if (argc > 1) {
        printf("usage: granule keys\nPrints every scene key (type, unit, default, range, meaning) as Markdown.\n");
        return strcmp(argv[1], "--help") && strcmp(argv[1], "-h") ? EXIT_REFUSED : EXIT_OK;
    }
    gr_scene_keys_markdown(stdout);
    return EXIT_OK;
}
