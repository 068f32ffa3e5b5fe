/* granule models: the registered collision models and their parameters; granule keys: every
 * scene key as Markdown (docs/scene-keys.md is its output). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "granule/model.h"
#include "granule/scene.h"

static const cli_opt models_opts[] = {
    {"--markdown", CLI_FLAG, NULL, 0, 0, 0, 0, NULL,
     "as Markdown tables (docs/models.md holds them)", NULL},
};

const cli_command cli_cmd_models = {
    .name = "models",
    .usage = "granule models [--markdown]",
    .about = "Lists every collision model, its kind and its parameters (unit, default, allowed "
             "range).\n",
    CLI_OPTS(models_opts),
};

/* the tables of the commands that take no option but --help */
const cli_command cli_cmd_keys = {
    .name = "keys",
    .usage = "granule keys",
    .about = "Prints every scene key (type, unit, default, range, meaning) as Markdown "
             "(docs/scene-keys.md).\n",
};

const cli_command cli_cmd_observables = {
    .name = "observables",
    .usage = "granule observables",
    .about = "Lists the observables of the analysis layer, their dimensions and parameters.\n",
};

int cmd_models(int argc, char **argv)
{
    bool markdown = false;
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_models, argc, argv, &markdown, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    int w_name = 8,
        w_unit = 5; /* the columns of the plain listing fit every model's longest name and unit */
    for (int m = 0; gr_models[m]; m++) {
        for (int i = 0; i < gr_models[m]->n_params; i++) {
            const int wn = (int)strlen(gr_models[m]->params[i].name),
                      wu = (int)strlen(gr_models[m]->params[i].unit);
            w_name = wn > w_name ? wn : w_name;
            w_unit = wu > w_unit ? wu : w_unit;
        }
    }
    for (int m = 0; gr_models[m]; m++) {
        const gr_model *md = gr_models[m];
        const char *kind = md->kind == GR_MODEL_NORMAL       ? "normal force law"
                           : md->kind == GR_MODEL_TANGENTIAL ? "tangential force law"
                           : md->kind == GR_MODEL_ROLLING    ? "rolling torque law"
                                                             : "event rule";
        printf(markdown ? "### `%s` (%s)\n\n%s\n\n" : "%s  [%s]\n  %s\n", md->name, kind,
               md->summary);
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
                    snprintf(range, sizeof range, "%c%g, %g%c", p->min_open ? '(' : '[', p->min,
                             p->max, p->max_open ? ')' : ']');
                }
                snprintf(def, sizeof def, "%g", p->def);
            }
            if (markdown) {
                printf("| `%s` | %s | %s | %s | %s |\n", p->name, p->unit, def, range, p->doc);
            } else {
                printf("    %-*s %-*s default %-8s range %-12s %s\n", w_name, p->name, w_unit,
                       p->unit, def, range, p->doc);
            }
        }
        printf("\n");
    }
    return EXIT_OK;
}

int cmd_keys(int argc, char **argv)
{
    cli_pos pos;
    const int parsed = cli_parse(&cli_cmd_keys, argc, argv, NULL, &pos);
    if (parsed >= 0) {
        return parsed;
    }
    gr_scene_keys_markdown(stdout);
    return EXIT_OK;
}
