"""Print the floating-point environment that numerical results depend on.

scripts/run_tests.sh prints it before each nbval run: numpy's SIMD kernels in use,
the OpenBLAS kernel (core type) and its thread count, and the CPU. A reader comparing
an nbval failure between two machines starts here.
"""

from __future__ import annotations

import os
import platform

import numpy as np
from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__


def main() -> None:
    simd = [x for x in __cpu_dispatch__ if __cpu_features__.get(x)]
    off = os.environ.get("NPY_DISABLE_CPU_FEATURES", "")
    try:
        from threadpoolctl import threadpool_info

        blas = [
            f"{p.get('internal_api')} {p.get('version')} kernel={p.get('architecture')}"
            f" threads={p.get('num_threads')}"
            for p in threadpool_info()
            if p.get("user_api") == "blas"
        ]
    except ImportError:
        blas = ["(threadpoolctl not installed)"]
    print(
        f"fp_environment: {platform.machine()} {platform.processor() or ''}".rstrip()
        + f"; numpy {np.__version__} SIMD in use: {' '.join(simd) or 'baseline only'}"
        + (f" (disabled: {off})" if off else "")
        + f"; BLAS: {'; '.join(blas)}"
    )


if __name__ == "__main__":
    main()
