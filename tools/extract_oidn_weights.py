#!/usr/bin/env python3
"""Extract Open Image Denoise's trained weights (TZA blobs) from its core library.

usage: python3 tools/extract_oidn_weights.py LIBOPENIMAGEDENOISE_CORE.so OUT_DIR

OIDN (Apache-2.0) compiles each trained network into libOpenImageDenoise_core as a read-only
byte array named oidn::blobs::weights::<name> (mangled `_ZN4oidn5blobs7weights<len><name>E`).
This script reads the library's ELF dynamic symbol table, finds the three networks lancer's
denoiser uses (the "rt" filter, HDR colour, without and with the auxiliary albedo and normal
images, quality "high" = OIDN's base models), checks that each is a well-formed TZA blob (magic
0x41D7, version 2, a tensor table whose entries lie inside the blob) and writes the bytes
unchanged to OUT_DIR/<name>.tza, then prints their SHA-256 digests for the provenance note.

The library comes with the `pyoidn` wheel, e.g.
  ~/.cache/lancer-peers/lib/python3.11/site-packages/pyoidn/oidn/lib/libOpenImageDenoise_core.so.2.5.1
No third-party Python module is needed.
"""
import hashlib
import os
import struct
import sys

NETWORKS = ("rt_hdr", "rt_hdr_alb", "rt_hdr_alb_nrm")


def elf_sections(data):
    """Section headers of a little-endian ELF64 file: list of (name, type, addr, offset, size, link, entsize)."""
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        raise SystemExit("not a little-endian 64-bit ELF file")
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x3A)
    raw = []
    for i in range(shnum):
        name, typ, _flags, addr, off, size, link, _info, _align, entsize = struct.unpack_from(
            "<IIQQQQIIQQ", data, shoff + i * shentsize)
        raw.append((name, typ, addr, off, size, link, entsize))
    strtab_off = raw[shstrndx][3]

    def cstr(base, idx):
        end = data.index(b"\0", base + idx)
        return data[base + idx:end].decode()

    return [(cstr(strtab_off, r[0]),) + r[1:] for r in raw]


def weight_symbols(data):
    """{name: (file offset, size)} of the oidn::blobs::weights::* symbols in .dynsym."""
    secs = elf_sections(data)
    dynsym = next(s for s in secs if s[0] == ".dynsym")
    dynstr = secs[dynsym[5]]
    out = {}
    prefix = "_ZN4oidn5blobs7weights"
    for i in range(dynsym[4] // dynsym[6]):
        st_name, _info, _other, _shndx, value, size = struct.unpack_from("<IBBHQQ", data, dynsym[3] + i * dynsym[6])
        end = data.index(b"\0", dynstr[3] + st_name)
        sym = data[dynstr[3] + st_name:end].decode()
        if not sym.startswith(prefix) or not sym.endswith("E"):
            continue
        rest = sym[len(prefix):-1]
        digits = len(rest) - len(rest.lstrip("0123456789"))
        name = rest[digits:digits + int(rest[:digits])]
        # virtual address -> file offset through the section that holds it
        sec = next(s for s in secs if s[2] <= value < s[2] + s[4] and s[1] != 8)  # not NOBITS
        out[name] = (value - sec[2] + sec[3], size)
    return out


def check_tza(blob, name):
    """Parse a TZA blob's header and table (OIDN core/tza.cpp); returns its tensors' names and shapes."""
    magic, major, _minor, table = struct.unpack_from("<HBBQ", blob, 0)
    if magic != 0x41D7 or major != 2:
        raise SystemExit(f"{name}: not a TZA v2 blob (magic {magic:#x}, version {major})")
    n, = struct.unpack_from("<I", blob, table)
    p = table + 4
    tensors = []
    for _ in range(n):
        ln, = struct.unpack_from("<H", blob, p)
        tname = blob[p + 2:p + 2 + ln].decode()
        p += 2 + ln
        ndims = blob[p]
        dims = struct.unpack_from(f"<{ndims}I", blob, p + 1)
        p += 1 + 4 * ndims
        layout = blob[p:p + ndims].decode()
        dtype = chr(blob[p + ndims])
        off, = struct.unpack_from("<Q", blob, p + ndims + 1)
        p += ndims + 9
        count = 1
        for d in dims:
            count *= d
        if dtype not in "hf" or off + count * (2 if dtype == "h" else 4) > len(blob):
            raise SystemExit(f"{name}: tensor {tname} lies outside the blob")
        tensors.append((tname, dims, layout, dtype))
    return tensors


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    with open(sys.argv[1], "rb") as f:
        data = f.read()
    syms = weight_symbols(data)
    os.makedirs(sys.argv[2], exist_ok=True)
    for name in NETWORKS:
        if name not in syms:
            raise SystemExit(f"{sys.argv[1]}: no oidn::blobs::weights::{name} (found {sorted(syms)})")
        off, size = syms[name]
        blob = data[off:off + size]
        tensors = check_tza(blob, name)
        with open(os.path.join(sys.argv[2], f"{name}.tza"), "wb") as f:
            f.write(blob)
        print(f"{name}.tza {size} bytes sha256 {hashlib.sha256(blob).hexdigest()} ({len(tensors)} tensors)")
        for t in tensors:
            print("   ", *t)


if __name__ == "__main__":
    main()
