#!/usr/bin/env bash
# The GPU checks in one call on a machine with an NVIDIA GPU (issue 17, goal 5). Stages,
# chosen by $STAGES (default "bench profile whole"), each under its own time limit:
#   bench      bench_gpu.py: 3 ms of the default case on $ARCHS (default: cuda with 16 steps
#              a compute graph, cuda with one step a launch from Python, and the host CPU),
#              side by side (times, element-steps/s, history differences);
#   profile    profile_gpu.py: where a GPU step's wall time goes (host launches or device
#              tasks); bench_graph.py: one step a launch against 16 a graph, alternating;
#   sample     profile_sample.py: an output sample's steps against the run's read-out;
#   whole      the whole default case with --arch cuda (the main command; checks, times),
#              with $FULL_GRAPH steps a graph (default 16; 1 where `bench` found the
#              graph failing on cuda);
#   python     the whole case again with one step a launch from Python (side by side);
#   multirate  bench_multirate.py on cuda: 3 levels against single-rate on the
#              convergence study's 0.125 mm local refinement;
#   ensemble   bench_ensemble.py on cuda: ensembles of $ENS_SIZES (default "1,4,16,64")
#              members of cases/single_passage.yaml, $ENS_MS ms (default 1) after the
#              preload each, their runs per minute (issue 45's table; a passage takes the
#              case's whole duration, so passages per minute = runs per minute x ENS_MS /
#              the case's duration_ms).
#   contact    bench_ensemble.py on cuda on issue 43's finest static level
#              (docs/results/contact_convergence: roller 0 and the spall zone at 0.0625 mm,
#              the other surfaces at 0.25 mm, the pressure law at alpha 30, the preload
#              mass-scaled): ensembles of $CONTACT_SIZES (default "1,4,16") members,
#              $CONTACT_MS ms (default 0.1) after the preload; what a passage on that mesh
#              costs on the GPU (a 6 ms passage = runs/min x CONTACT_MS / 6).
# Every stage shares one kernel cache (/tmp/bg/cache_cuda). Each stage's limit must leave
# room for compiling: Taichi writes its offline cache when a process ends, so a process
# killed while compiling leaves nothing for the next (seen: 8 steps a launch took 113 s to
# compile on an H200's host). The default stages' limits add up to 560 s, within one
# device call's 600 s.
# Logs and the returned files go to $OUT (default /tmp/gpu_check). Packages missing on a
# machine without network can be carried in .gpu/ (ignored by git): taichi_trim.tar.xz
# (the taichi 1.7.4 cp312 manylinux wheel unzipped, without taichi/_lib/c_api,
# taichi-1.7.4.data, taichi/assets and taichi/examples: 23 MB instead of 56), the meshio
# and dill wheels, and a numpy 1.26 wheel in .gpu/np/ used only if Taichi fails to start
# with the installed numpy. Fetch the wheels with `pip download --no-deps --only-binary
# :all: --python-version 3.12 --platform manylinux_2_27_x86_64 ...`.
#
#   bash benchmarks/taichi_bearing/gpu_check.sh
#   STAGES="sample whole python" bash benchmarks/taichi_bearing/gpu_check.sh
set -u -o pipefail
OUT=${OUT:-/tmp/gpu_check}
mkdir -p "$OUT"
LOG=$OUT/log.txt
export PYTHONUNBUFFERED=1 TI_SKIP_VERSION_CHECK=ON
PY=${PYTHON:-python3}
if [ -d .gpu ]; then
    SITE=/tmp/site
    mkdir -p $SITE
    tar -xJf .gpu/taichi_trim.tar.xz -C $SITE || exit 1
    $PY -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --target $SITE \
        .gpu/*.whl || exit 1
    export PYTHONPATH=$SITE
fi
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm --format=csv | tee -a "$LOG"
start='import taichi as ti; ti.init(arch=ti.cuda, default_fp=ti.f64); '
start+='print("taichi on", ti.lang.impl.current_cfg().arch)'
msg=$($PY -c "$start" 2>&1 | tail -5)
echo "$msg" | tee -a "$LOG"
if [[ "$msg" != *"taichi on Arch.cuda"* && -d .gpu/np ]]; then
    echo "Taichi did not start on cuda; retrying with numpy 1.26" | tee -a "$LOG"
    $PY -m pip install -q --no-index --no-deps --no-compile --target $SITE .gpu/np/*.whl
    $PY -c "$start" 2>&1 | tail -5 | tee -a "$LOG"
fi

STAGES=" ${STAGES:-bench profile whole} "
FULL_GRAPH=${FULL_GRAPH:-16}
export TAICHI_BEARING_CACHE_DIR=/tmp/bg/cache_cuda
want() { [[ "$STAGES" == *" $1 "* ]]; }

if want bench; then
    ARCHS=${ARCHS:-cuda:g16 cuda cpu}  # not `:=` in the pipe below: a subshell's
    echo "== bench: bench_gpu, 3 ms, $ARCHS" | tee -a "$LOG"
    # shellcheck disable=SC2086  # the backends are separate words
    timeout "${BENCH_S:-200}" $PY benchmarks/taichi_bearing/bench_gpu.py --archs $ARCHS --duration-ms 3 \
        --keep /tmp/bg 2>&1 | tee -a "$LOG"
    for run in /tmp/bg/run_*; do
        [ -f "$run/histories.parquet" ] && cp "$run/histories.parquet" "$OUT/h3_${run##*/run_}.parquet"
    done
    if grep -q "cuda:g16: FAILED" "$LOG"; then
        FULL_GRAPH=1  # the graph did not run on cuda: the whole case as before
    fi
fi

if want profile; then
    echo "== profile: profile_gpu, 2000 steps, 16 a graph; bench_graph" | tee -a "$LOG"
    TAICHI_BEARING_STEPS_PER_GRAPH=16 TI_KERNEL_PROFILER=1 timeout "${PROFILE_S:-80}" \
        $PY benchmarks/taichi_bearing/profile_gpu.py --arch cuda --steps 2000 2>&1 | grep -v '^\[Taichi\]' \
        | head -60 | tee -a "$LOG"
    timeout "${GRAPH_S:-80}" $PY benchmarks/taichi_bearing/bench_graph.py cases/line_spall.yaml --arch cuda \
        --threads 0 2>&1 | grep -v '^\[Taichi\]' | tee -a "$LOG"
fi

if want sample; then
    echo "== sample: profile_sample, 20 samples" | tee -a "$LOG"
    timeout "${SAMPLE_S:-80}" $PY benchmarks/taichi_bearing/profile_sample.py --arch cuda --samples 20 2>&1 \
        | grep -v '^\[Taichi\]' | tee -a "$LOG"
fi

whole() {  # the whole default case on cuda, $1 steps a graph, into /tmp/full_$1
    echo "== whole: the default case on cuda, $1 steps a graph" | tee -a "$LOG"
    TAICHI_BEARING_STEPS_PER_GRAPH=$1 timeout "$2" $PY -m taichi_bearing cases/line_spall.yaml \
        --arch cuda --no-post --out "/tmp/full_$1" --set output.frames=false \
        --progress-interval 10 2>&1 | grep -v '^\[Taichi\]' | tee -a "$LOG"
    cp "/tmp/full_$1/summary.json" "$OUT/summary_full_g$1.json" 2>/dev/null
    cp "/tmp/full_$1/histories.parquet" "$OUT/h_full_g$1.parquet" 2>/dev/null
}
want whole && whole "$FULL_GRAPH" "${FULL_S:-200}"
want python && whole 1 "${PYTHON_S:-150}"

if want multirate; then
    echo "== multirate: bench_multirate on cuda, levels 0 and 3, 4000 steps" | tee -a "$LOG"
    timeout "${MULTIRATE_S:-150}" $PY benchmarks/taichi_bearing/bench_multirate.py --arch cuda --levels 0 3 \
        --repeats 1 --steps 4000 2>&1 | grep -v '^\[Taichi\]' | tee -a "$LOG"
fi
if want ensemble; then
    echo "== ensemble: bench_ensemble on cuda, sizes ${ENS_SIZES:-1,4,16,64}" | tee -a "$LOG"
    timeout "${ENSEMBLE_S:-400}" $PY benchmarks/taichi_bearing/bench_ensemble.py --arch cuda \
        --case cases/single_passage.yaml --sizes "${ENS_SIZES:-1,4,16,64}" \
        --duration-ms "${ENS_MS:-1}" 2>&1 | grep -v '^\[Taichi\]' | tee -a "$LOG"
fi
if want contact; then
    echo "== contact: bench_ensemble on cuda, issue 43's finest level, sizes ${CONTACT_SIZES:-1,4,16}" \
        | tee -a "$LOG"
    timeout "${CONTACT_S:-400}" $PY benchmarks/taichi_bearing/bench_ensemble.py --arch cuda \
        --case cases/single_passage.yaml --sizes "${CONTACT_SIZES:-1,4,16}" \
        --duration-ms "${CONTACT_MS:-0.1}" \
        --set mesh.spall_size_mm=0.0625 --set mesh.roller_surface_size_mm=0.0625 \
        --set mesh.surface_size_mm=0.25 --set mesh.fine_rollers=1 --set mesh.spall_zone_mm=6 \
        --set contact.penalty_method=pressure --set contact.penalty_scale=30 \
        --set run.time_step=global --set preload.mass_scaling=true \
        --set preload.max_steps=2000000 --set run.frame_interval_ms=0.05 \
        --set run.checkpoint_interval_ms=0.05 2>&1 | grep -v '^\[Taichi\]' | tee -a "$LOG"
fi
exit 0
