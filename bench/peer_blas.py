"""The BLAS a Python peer (numpy, scipy, scikit-learn, umap-learn) runs on, for the benchmarks
that time one beside MotionMap: users run them on OpenBLAS (pip's numpy ships it; on Debian
libopenblas0-pthread), Debian's numpy defaults to the reference BLAS (one core, unblocked).

Get OpenBLAS without switching the system's BLAS (`apt-get install libopenblas0-pthread` would
make it the default BLAS of every program on the machine, through update-alternatives):

    cd /tmp && apt-get download libopenblas0-pthread &&
        dpkg -x libopenblas0-pthread_*.deb /opt/openblas

and point only the peer's process at it with openblas_env(). Importing this module loads no BLAS.
"""
import os

# Debian's libopenblas0-pthread, installed or unpacked with dpkg -x into /opt/openblas.
OPENBLAS_DIRS = ["/usr/lib/x86_64-linux-gnu/openblas-pthread",
                 "/opt/openblas/usr/lib/x86_64-linux-gnu/openblas-pthread"]
# The caller's kernel choice, replaced by openblas_env().
CORETYPE_VARS = ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")
GET_OPENBLAS = ("cd /tmp && apt-get download libopenblas0-pthread && "
                "dpkg -x libopenblas0-pthread_*.deb /opt/openblas")


def openblas_dir(given=None):
    """`given`, else the first of OPENBLAS_DIRS, if it holds libblas.so.3 and liblapack.so.3."""
    for folder in [given] if given else OPENBLAS_DIRS:
        if all(os.path.exists(os.path.join(folder, lib))
               for lib in ("libblas.so.3", "liblapack.so.3")):
            return os.path.realpath(folder)
    return None


def on_path(folder, env=os.environ):
    """Whether `folder` is in env's LD_LIBRARY_PATH already."""
    path = env.get("LD_LIBRARY_PATH", "")
    return folder in [os.path.realpath(p) for p in path.split(":") if p]


def cpu_kernel():
    """The OpenBLAS kernel for this processor's instruction set: SkylakeX (AVX-512), Haswell
    (AVX2 and FMA), or None (let OpenBLAS choose).

    Debian 12's OpenBLAS 0.3.21 does not know every processor model: on a virtual "Intel Xeon
    Processor" with AVX-512 it falls back to its Prescott (SSE3) kernel and multiplies matrices
    at a fifth of the speed (dgemm on 2 threads: 9 against 42 GFLOP/s with SkylakeX). A user's
    pip-installed numpy, whose newer OpenBLAS detects the features, runs the fast kernel; so the
    peer gets the kernel the features allow."""
    try:
        with open("/proc/cpuinfo") as f:
            flags = next((set(line.split(":", 1)[1].split()) for line in f
                          if line.startswith("flags")), set())
    except OSError:
        return None
    if {"avx512f", "avx512bw", "avx512dq", "avx512vl"} <= flags:
        return "SkylakeX"
    if {"avx2", "fma"} <= flags:
        return "Haswell"
    return None


def openblas_env(folder, env=os.environ):
    """A copy of `env` whose processes load OpenBLAS from `folder` (first in LD_LIBRARY_PATH)
    with the kernel of cpu_kernel() (OPENBLAS_CORETYPE; the caller's CORETYPE variables are
    dropped)."""
    out = dict(env)
    path = env.get("LD_LIBRARY_PATH", "")
    out["LD_LIBRARY_PATH"] = folder + (":" + path if path else "")
    for v in CORETYPE_VARS:
        out.pop(v, None)
    kernel = cpu_kernel()
    if kernel:
        out["OPENBLAS_CORETYPE"] = kernel
    return out


def peer_blas():
    """(lines describing the thread pools this process loaded, whether its BLAS is a tuned,
    threaded one). threadpoolctl does not see the reference BLAS: /proc/self/maps names it."""
    from threadpoolctl import threadpool_info
    lines, tuned = [], False
    for pool in threadpool_info():
        extra = ""
        if pool.get("internal_api") == "openblas":
            extra = f", {pool.get('threading_layer')}, kernel {pool.get('architecture')}"
        tuned = tuned or pool.get("user_api") == "blas"
        version = f" {pool['version']}" if pool.get("version") else ""
        lines.append(f"{pool['user_api']}: {pool['internal_api']}{version}, "
                     f"{pool['num_threads']} threads{extra} ({pool['filepath']})")
    if not tuned:
        with open("/proc/self/maps") as f:
            libs = sorted({os.path.realpath(line.split()[-1]) for line in f
                           if "/libblas" in line or "/liblapack" in line})
        lines.insert(0, f"blas: reference BLAS/LAPACK, 1 thread ({', '.join(libs)})")
    return lines, tuned
