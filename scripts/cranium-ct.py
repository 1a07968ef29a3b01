#!/usr/bin/python3
"""Converts InVesalius' sample head CT (Debian's invesalius-examples) into a NRRD Penumbra reads.

Cranium.inv3 is a gzip tar holding the CT as a raw voxel block (matrix.dat, int16 Hounsfield
units, little endian, x fastest) and main.plist naming its shape (z, y, x), type and spacing.
The NRRD gets the same voxels with the key/value `penumbra_units:=HU`, which marks its values as
Hounsfield units. Standard library only (tarfile, plistlib), so Debian's python3 runs it as is.

usage: cranium-ct.py OUT.nrrd [Cranium.inv3]
An existing OUT newer than the .inv3 is kept; the file is written beside OUT and renamed into
place, so a reader never sees half of it.
"""

import os
import plistlib
import sys
import tarfile

DEFAULT_SOURCE = "/usr/share/doc/invesalius-examples/examples/Cranium.inv3"
NRRD_TYPES = {"int16": "short", "uint16": "ushort", "uint8": "uchar", "float32": "float"}


def member(archive, name):
    """The archive's member whose file name is `name` (the .inv3 keeps them in a temp folder)."""
    for info in archive.getmembers():
        if info.isfile() and os.path.basename(info.name) == name:
            return archive.extractfile(info)
    raise SystemExit(f"cranium-ct: no {name} in the archive")


def convert(source, out):
    with tarfile.open(source, "r:gz") as archive:
        main = plistlib.load(member(archive, "main.plist"))
        matrix = main["matrix"]
        dtype = matrix["dtype"]
        if dtype not in NRRD_TYPES:
            raise SystemExit(f"cranium-ct: unexpected voxel type {dtype}")
        depth, height, width = (int(n) for n in matrix["shape"])
        spacing = [float(s) for s in main["spacing"]]
        voxels = member(archive, matrix["filename"]).read()
    bytes_per_voxel = {"int16": 2, "uint16": 2, "uint8": 1, "float32": 4}[dtype]
    expected = width * height * depth * bytes_per_voxel
    if len(voxels) != expected:
        raise SystemExit(f"cranium-ct: {matrix['filename']} holds {len(voxels)} bytes, "
                         f"expected {expected} for {width}x{height}x{depth} {dtype}")
    units = "HU" if main.get("modality") == "CT" else "none"
    header = (
        "NRRD0004\n"
        f"# {main.get('name', 'CT')} from {os.path.basename(source)} (InVesalius sample, GPL-2)\n"
        f"type: {NRRD_TYPES[dtype]}\n"
        "dimension: 3\n"
        f"sizes: {width} {height} {depth}\n"
        f"spacings: {spacing[0]:.9g} {spacing[1]:.9g} {spacing[2]:.9g}\n"
        "endian: little\n"
        "encoding: raw\n"
        f"penumbra_units:={units}\n"
        "\n")
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    partial = out + ".partial"
    with open(partial, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(voxels)
    os.replace(partial, out)


def main():
    if len(sys.argv) not in (2, 3):
        raise SystemExit("usage: cranium-ct.py OUT.nrrd [Cranium.inv3]")
    out = sys.argv[1]
    source = sys.argv[2] if len(sys.argv) == 3 else DEFAULT_SOURCE
    if not os.path.isfile(source):
        raise SystemExit(f"cranium-ct: {source} is missing (apt-get install invesalius-examples)")
    if os.path.isfile(out) and os.path.getmtime(out) >= os.path.getmtime(source):
        return
    convert(source, out)


if __name__ == "__main__":
    main()
