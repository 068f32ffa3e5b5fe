#!/bin/bash
# The layering of docs/architecture.md, checked on the source (the build checks it on the
# symbols): each folder includes only the private headers of layers below it, the core (src/core)
# names no integrator and no scene, everything reaches the integrators through their interface
# (granule/integrator.h), and the library never prints to stderr/stdout or aborts.
# Usage: test_layers.sh SOURCE_ROOT
set -u
root=$1
fail=0
bad() { echo "FAIL: $*"; fail=1; }

# The layers, bottom to top (docs/architecture.md; meson.build links each only with those below,
# so an upward call fails the build). Here the same order is checked on the #include lines: a
# file includes no private header of a layer above its own.
layers="base models core integrators io analysis collide scene theory app cli"
rank() { local i=0; for l in $layers; do [ "$l" = "$1" ] && { echo $i; return; }; i=$((i + 1)); done; echo -1; }
for dir in "$root"/src/*/ "$root"/models/; do
    layer=$(basename "$dir")
    own=$(rank "$layer")
    [ "$own" -ge 0 ] || { bad "src/$layer is not a layer of docs/architecture.md ($layers)"; continue; }
    while IFS=: read -r file line inc; do
        to=${inc%%/*}
        [ "$(rank "$to")" -le "$own" ] || bad "${file#$root/}:$line ($layer) includes $inc, a layer above it"
    done < <(grep -rno '#include "[a-z_]*/[a-z_/]*\.h"' "$dir" --include='*.[ch]' | sed 's/#include "\(.*\)"/\1/')
done
core_names=$(grep -nw 'gr_scene\|gr_event_[a-z_]*\|gr_hybrid_[a-z_]*\|gr_verlet_[a-z_]*\|gr_integrator_verlet\|gr_integrator_event\|gr_integrator_hybrid\|gr_integrator_names\|gr_integrator_find\|gr_blocking\|gr_histogram' "$root"/src/core/*.[ch] | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$core_names" ] || bad "src/core names an integrator, the registry or the scene:"$'\n'"$core_names"
# the scene stops at its own layer: everything below it takes plain parameter structs
# (gr_sim_params, gr_obs_setup, gr_collide_setup, gr_traj_setup) and names no scene, neither its
# header nor its type (the scene fills them: src/scene/scene_sim.c)
below_scene=$(grep -rnw 'gr_scene\|granule/scene\.h' "$root"/src/base "$root"/models "$root"/src/core "$root"/src/integrators \
    "$root"/src/io "$root"/src/analysis "$root"/src/collide --include='*.[ch]' | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$below_scene" ] || bad "a layer below the scene names it (take a plain parameter struct):"$'\n'"$below_scene"
# ... and the analysis layer evaluates no contact law: a force of a frame comes from the force kernel's own law
# (gr_contact_virial, src/core/kernels.c), never from a copy of its coefficients' formula
analysis_laws=$(grep -nw 'k_s\|gamma_n\|gamma_t\|gr_contact_prepare\|gr_normal_[a-z_]*\|gr_tangential_[a-z_]*' "$root"/src/analysis/*.[ch] | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$analysis_laws" ] || bad "src/analysis evaluates a contact law itself (use gr_contact_virial):"$'\n'"$analysis_laws"
# below the application layer nothing tests a model or an integrator by its name: capability
# flags say what a law or an integrator can do (gr_model, gr_integrator_type)
name_tests=$(grep -rnE 'strcmp\([a-z_.>-]*(normal|tangential|rolling|integrator|model)->name, "' "$root"/src "$root"/models --include='*.[ch]' |
    grep -v "^$root/src/app/\|^$root/src/cli/" | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$name_tests" ] || bad "a model or integrator tested by name below the application layer (use a capability flag):"$'\n'"$name_tests"
# the run driver and everything but the integrators' own folders use the integrator interface
int_includes=$(grep -rn '#include "integrators/' "$root"/src --include='*.[ch]' | grep -v "^$root/src/integrators/")
[ -z "$int_includes" ] || bad "an integrator header included outside src/integrators:"$'\n'"$int_includes"
# a model is closed over its physics: models/ includes only the public API and other models
# (its restitution formulas, calibration and reference force live in its own file, not in src/)
model_includes=$(grep -n '#include "' "$root"/models/*.[ch] | grep -v '#include "\(models\|granule\)/')
[ -z "$model_includes" ] || bad "models/ includes a file of src/ (model physics belongs in models/):"$'\n'"$model_includes"
# a model's own parameters (the keys only it, or a law it builds on, declares: hard_sphere's beta,
# hertz's k_h, ...) are read by the models' prepare only; the rest of the tree reads the
# coefficients prepare derived from them (gr_contact_coeffs, the slots the model's file names)
own_keys='tc|k_h|viscoelastic|visco_A|v_max|beta|beta_mu|mu_r|kt_ratio|k_t|gamma_t|mindlin'
own_reads=$(grep -rnE "(contact|\bp)\.($own_keys)\b" "$root"/src --include='*.[ch]' | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$own_reads" ] || bad "src/ reads a model's own parameter (read its coefficients instead):"$'\n'"$own_reads"
# every integrator folder is registered
for d in "$root"/src/integrators/*/; do
    name=$(basename "$d")
    grep -q "&gr_integrator_$name," "$root/src/integrators/registry.c" || bad "src/integrators/$name is not in registry.c"
done
# the library never prints or aborts: it returns status and messages to its caller (the CLI, Python);
# above it, the application layer speaks on the terminal only through src/app/report.c
lib_prints=$(grep -rn 'f\(printf\|puts\|putc\|write\)([^;]*\bstd\(err\|out\)\b\|[^a-z_]printf(\|[^a-z_]puts(\|[^a-z_]putchar(\|[^a-z_]abort()\|[^a-z_]perror(' \
    "$root"/src "$root"/models --include='*.[ch]' | grep -v "^$root/src/cli/\|^$root/src/app/report.c:" | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$lib_prints" ] || bad "the library prints or aborts (only src/cli may):"$'\n'"$lib_prints"
[ $fail = 0 ] && echo "layers: ok ($layers, each including only those below; integrators behind their interface; no scene below the scene layer, no contact law in src/analysis; models free of src/ and closed over their parameters; the library does not print)"
exit $fail
