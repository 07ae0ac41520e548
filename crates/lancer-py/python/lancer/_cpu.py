"""The CPU check that runs before lancer's native module is loaded.

The module is compiled for x86-64-v3 (AVX2 and FMA: Intel Haswell, AMD Zen and later), like
lancer's command line, so that every machine renders the same bits. On an older CPU its code
would die of an illegal instruction; instead `import lancer` raises ImportError and says how
to build one for any x86-64 CPU. The check reads /proc/cpuinfo (Linux); only when AVX2 or FMA
is missing does it look at the native library itself, through ctypes (a read of one byte of
data, no code of the library runs), to see whether it was built for x86-64-v3 at all.
"""

import ctypes
import glob
import importlib.machinery
import os
import platform

REBUILD = 'RUSTFLAGS="-C target-cpu=x86-64" pip install --force-reinstall ./crates/lancer-py'


def cpu_flags(path="/proc/cpuinfo"):
    """The CPU's feature flags (a set of names such as 'avx2'), or None where unknown."""
    try:
        with open(path, encoding="ascii", errors="replace") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() == "flags":
                    return set(value.split())
    except OSError:
        pass
    return None


def native_needs_x86_64_v3(package_dir=None):
    """True when the native library beside this file was compiled for x86-64-v3."""
    package_dir = package_dir or os.path.dirname(os.path.abspath(__file__))
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        for path in glob.glob(os.path.join(package_dir, "_lancer" + suffix)):
            try:
                lib = ctypes.CDLL(path)
                return ctypes.c_uint8.in_dll(lib, "LANCER_NEEDS_X86_64_V3").value == 1
            except (OSError, ValueError):
                return True
    return True


def check(flags=None, needs_v3=None):
    """Raises ImportError when this CPU cannot run the native library.

    `flags` (the CPU's feature flags) and `needs_v3` (a function telling whether the library
    needs x86-64-v3) default to this machine's; they are parameters for the tests.
    """
    if flags is None:
        if platform.machine().lower() not in ("x86_64", "amd64"):
            return
        flags = cpu_flags()
        if flags is None:
            return
    missing = sorted({"avx2", "fma"} - set(flags))
    if not missing:
        return
    if not (needs_v3 or native_needs_x86_64_v3)():
        return
    raise ImportError(
        "lancer's native module was built for x86-64-v3 CPUs (AVX2 and FMA), and this CPU "
        f"lacks {' and '.join(m.upper() for m in missing)}. Build one for any x86-64 CPU from "
        f"the repository with: {REBUILD}"
    )
