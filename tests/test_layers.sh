#!/bin/bash
# The layering of docs/architecture.md, checked on the source: the core (src/core) knows no
# integrator and no io (it takes a gr_sim_params and hands its state to a byte buffer), and the
# run driver reaches the integrators only through their interface (granule/integrator.h); the
# library (everything but src/cli) never prints to stderr/stdout or aborts.
# Usage: test_layers.sh SOURCE_ROOT
set -u
root=$1
fail=0
bad() { echo "FAIL: $*"; fail=1; }

core_includes=$(grep -n '#include "\(io\|event\|hybrid\|integrators\|analysis\|cli\|theory\)/' "$root"/src/core/*.[ch])
[ -z "$core_includes" ] || bad "src/core includes a layer above it:"$'\n'"$core_includes"
core_names=$(grep -nw 'gr_scene\|gr_event_[a-z_]*\|gr_hybrid_[a-z_]*\|gr_verlet_[a-z_]*\|gr_integrator_verlet\|gr_integrator_event\|gr_integrator_hybrid\|gr_blocking\|gr_histogram' "$root"/src/core/*.[ch] | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$core_names" ] || bad "src/core names an integrator or the scene:"$'\n'"$core_names"
# the integrators build on the core, never on io
int_includes=$(grep -rn '#include "io/' "$root"/src/integrators)
[ -z "$int_includes" ] || bad "src/integrators includes io:"$'\n'"$int_includes"
# the run driver and the rest of io call the integrator interface, not an integrator
io_includes=$(grep -rn '#include "integrators/' "$root"/src/io "$root"/src/cli "$root"/src/analysis)
[ -z "$io_includes" ] || bad "io / cli / analysis include an integrator directly:"$'\n'"$io_includes"
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
# the library never prints or aborts: it returns status and messages to its caller (the CLI, Python)
lib_prints=$(grep -rn 'f\(printf\|puts\|putc\|write\)([^;]*\bstd\(err\|out\)\b\|[^a-z_]printf(\|[^a-z_]puts(\|[^a-z_]putchar(\|[^a-z_]abort()\|[^a-z_]perror(' \
    "$root"/src "$root"/models --include='*.[ch]' | grep -v "^$root/src/cli/" | grep -v '^[^:]*:[0-9]*: *\(/\*\|\*\)')
[ -z "$lib_prints" ] || bad "the library prints or aborts (only src/cli may):"$'\n'"$lib_prints"
[ $fail = 0 ] && echo "layers: ok (core free of io and of integrators; models free of src/; run driver uses the interface; the library does not print)"
exit $fail
