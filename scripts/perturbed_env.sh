# Sourced by scripts/run_tests.sh and scripts/nbval_chapter.sh (needs PY set).
# Defines `perturbed CMD...`: run CMD in a floating-point environment that imitates
# another CPU, with all three of these changes:
#   - OpenBLAS forced onto another kernel (OPENBLAS_CORETYPE=Prescott, SSE3 only;
#     Nehalem if the machine is already set to Prescott);
#   - numpy's SIMD dispatch groups that this CPU has turned off
#     (NPY_DISABLE_CPU_FEATURES: X86_V3 on an AVX2 machine, "X86_V3 X86_V4 AVX512_ICL"
#     on an AVX-512 one, as numpy reports them): numpy falls back to its baseline
#     kernels for exp, log, sin, sums, ...;
#   - one thread for OpenBLAS and OpenMP (another summation order in BLAS).
# A number that moves there is printed with more digits than its computation has.
pert_core=Prescott
[ "${OPENBLAS_CORETYPE:-}" = Prescott ] && pert_core=Nehalem
pert_simd=$("$PY" -c 'from numpy._core._multiarray_umath import __cpu_dispatch__ as d, __cpu_features__ as f; print(" ".join(x for x in d if f.get(x)))')

perturbed() {  # perturbed CMD...: run CMD (a command or a shell function) perturbed
    (
        export OPENBLAS_CORETYPE="$pert_core" NPY_DISABLE_CPU_FEATURES="$pert_simd" \
            OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
        "$PY" scripts/fp_environment.py
        "$@"
    )
}
