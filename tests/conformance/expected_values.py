#!/usr/bin/python3
"""Writes, as JSON on stdout, what nibabel and pydicom read from the volume files that Debian's
packages ship (python3-nibabel's tests/data, python3-pydicom's test files, insighttoolkit5-examples,
heudiconv's test data): for each file in a format Penumbra reads, its package, path, and, where
the reference reader opens it, dimensions, spacing, axes and origin in RAS, the value range and a
sample of voxels. Penumbra's conformance test compares its own loads with these.

Run with Debian's /usr/bin/python3 (nibabel, pydicom, numpy).
"""

import glob
import json
import os
import sys
import warnings

import numpy as np

PACKAGES = {
    "python3-nibabel": "/usr/lib/python3/dist-packages/nibabel/tests/data",
    "python3-pydicom": "/usr/lib/python3/dist-packages/pydicom/data/test_files",
    "insighttoolkit5-examples": "/usr/share/doc/insighttoolkit5-examples/examples/Data",
    "heudiconv": "/usr/lib/python3/dist-packages/heudiconv/tests/data",
}

# The names of Penumbra's formats (volume.hpp's load_volume): NIfTI (with .hdr/.img pairs),
# NRRD, raw, DICOM by extension. Other formats in these folders (MINC, PAR/REC, MGH, AFNI,
# MetaImage, GIFTI, tractography) are not Penumbra's and are not listed.
SUFFIXES = (".nii", ".nii.gz", ".hdr", ".nrrd", ".nhdr", ".dcm")

# Voxels sampled per file: fixed fractions of each dimension, so the choice is reproducible.
FRACTIONS = (0.0, 0.25, 0.5, 0.75, 1.0)


def sample_indices(dims):
    seen = []
    for fx in FRACTIONS:
        for fy in FRACTIONS:
            for fz in FRACTIONS:
                index = tuple(int(round(f * (d - 1))) for f, d in zip((fx, fy, fz), dims))
                if index not in seen:
                    seen.append(index)
    return seen


def finite_or_none(value):
    value = float(value)
    return value if np.isfinite(value) else None


def geometry(dims, steps, origin):
    """steps: 3x3, columns = RAS step per index axis."""
    steps = np.asarray(steps, dtype=float)
    spacing = np.linalg.norm(steps, axis=0)
    axes = steps / np.where(spacing > 0, spacing, 1.0)
    return {
        "dims": [int(d) for d in dims],
        "spacing": spacing.tolist(),
        "axes": axes.T.tolist(),  # one list per index axis
        "origin": [float(v) for v in origin],
    }


def nifti_expected(path):
    import nibabel as nib

    image = nib.load(path)
    header = image.header
    shape = tuple(image.shape) + (1,) * (3 - len(image.shape))
    dims = shape[:3]
    # NIfTI's rule, which Penumbra follows: the sform when its code is set, else the qform, else
    # pixdim alone ("method 1"; nibabel's fallback would be an Analyze-style LAS affine instead).
    sform_code = int(header["sform_code"]) if "sform_code" in header else 0
    qform_code = int(header["qform_code"]) if "qform_code" in header else 0
    if sform_code > 0:
        affine = header.get_sform()
    elif qform_code > 0:
        affine = header.get_qform()
    else:
        zooms = [abs(float(z)) if float(z) != 0 and np.isfinite(float(z)) else 1.0
                 for z in header.get_zooms()[:3]]
        zooms += [1.0] * (3 - len(zooms))
        affine = np.diag(zooms + [1.0])
    result = geometry(dims, affine[:3, :3], affine[:3, 3])
    result["sform_code"] = sform_code
    result["qform_code"] = qform_code
    data = np.asanyarray(image.dataobj)
    data = data.reshape(data.shape + (1,) * (3 - data.ndim))
    while data.ndim > 3:
        data = data[..., 0]
    if data.dtype.kind == "c" or data.dtype.fields is not None:
        result["values"] = None
        return result
    values = data.astype(np.float64)
    finite = values[np.isfinite(values)]
    result["range"] = [float(finite.min()), float(finite.max())] if finite.size else None
    result["samples"] = [[i, j, k, finite_or_none(values[i, j, k])]
                         for i, j, k in sample_indices(dims)]
    return result


def mosaic_expected(dataset):
    """A Siemens mosaic as nibabel unpacks it (its MosaicWrapper: tiles, position correction and
    the CSA slice normal), or None for other images. nibabel's arrays are (row, column, slice)."""
    from nibabel.nicom import dicomwrappers

    try:
        wrapper = dicomwrappers.wrapper_from_data(dataset)
    except Exception:
        return None
    if not getattr(wrapper, "is_mosaic", False):
        return None
    data = np.asarray(wrapper.get_data(), dtype=np.float64)
    rows, columns, slices = data.shape
    affine = np.asarray(wrapper.affine, dtype=np.float64)
    lps_to_ras = np.diag([-1.0, -1.0, 1.0])
    # Penumbra's index axes: i along a row (nibabel's column index), j down a column, k slices.
    steps = lps_to_ras @ affine[:3, [1, 0, 2]]
    result = geometry((columns, rows, slices), steps, lps_to_ras @ affine[:3, 3])
    result["modality"] = str(getattr(dataset, "Modality", ""))
    result["range"] = [float(data.min()), float(data.max())]
    result["samples"] = [[i, j, k, float(data[j, i, k])]
                         for i, j, k in sample_indices((columns, rows, slices))]
    return result


def dicom_expected(path):
    import pydicom
    from pydicom.pixel_data_handlers.util import apply_modality_lut

    dataset = pydicom.dcmread(path, force=True)
    mosaic = mosaic_expected(dataset)
    if mosaic is not None:
        return mosaic
    if "PixelData" not in dataset or "Columns" not in dataset:
        return {"note": "no pixel data"}
    columns, rows = int(dataset.Columns), int(dataset.Rows)
    frames = int(getattr(dataset, "NumberOfFrames", 1) or 1)
    spacing = getattr(dataset, "PixelSpacing", None)
    result = {"dims": [columns, rows, frames], "modality": str(getattr(dataset, "Modality", ""))}
    if spacing is not None:
        result["pixel_spacing"] = [float(spacing[1]), float(spacing[0])]
    orientation = getattr(dataset, "ImageOrientationPatient", None)
    position = getattr(dataset, "ImagePositionPatient", None)
    lps_to_ras = np.array([-1.0, -1.0, 1.0])
    if orientation is not None and len(orientation) == 6:
        row = np.array([float(v) for v in orientation[:3]])
        column = np.array([float(v) for v in orientation[3:]])
        normal = np.cross(row, column)
        result["axes_ij"] = [(row / np.linalg.norm(row) * lps_to_ras).tolist(),
                             (column / np.linalg.norm(column) * lps_to_ras).tolist()]
        if frames == 1:
            result["axes"] = result["axes_ij"] + [(normal / np.linalg.norm(normal) * lps_to_ras).tolist()]
    if position is not None and frames == 1:
        result["origin"] = (np.array([float(v) for v in position]) * lps_to_ras).tolist()
    try:
        pixels = dataset.pixel_array
    except Exception as error:  # the reference cannot decode it either
        result["values"] = None
        result["reference_error"] = str(error).splitlines()[0][:200]
        return result
    values = np.asarray(apply_modality_lut(pixels, dataset), dtype=np.float64)
    # A dose grid's values in Gy: DoseGridScaling, where no rescale is given.
    if "DoseGridScaling" in dataset and "RescaleSlope" not in dataset:
        values = values * float(dataset.DoseGridScaling)
    if str(getattr(dataset, "PhotometricInterpretation", "")) == "MONOCHROME1":
        result["monochrome1"] = True
    result["range"] = [float(values.min()), float(values.max())]
    if frames == 1 and values.ndim == 2:
        result["samples"] = [[i, j, 0, float(values[j, i])]
                             for i, j, _ in sample_indices((columns, rows, 1))]
    return result


def candidates():
    for package, folder in PACKAGES.items():
        for path in sorted(glob.glob(os.path.join(folder, "**", "*"), recursive=True)):
            name = os.path.basename(path).lower()
            if os.path.isfile(path) and name.endswith(SUFFIXES):
                yield package, path


def main():
    warnings.simplefilter("ignore")
    entries = []
    for package, path in candidates():
        entry = {"package": package, "path": path}
        name = path.lower()
        try:
            if name.endswith((".nii", ".nii.gz", ".hdr")):
                entry["reader"] = "nibabel"
                entry["expected"] = nifti_expected(path)
            elif name.endswith(".dcm"):
                entry["reader"] = "pydicom"
                entry["expected"] = dicom_expected(path)
            else:
                entry["reader"] = None  # NRRD: no reference reader in Debian's Python
        except Exception as error:
            entry["reference_error"] = (type(error).__name__ + ": " + str(error)).splitlines()[0][:200]
        entries.append(entry)
    json.dump(entries, sys.stdout, indent=1)


if __name__ == "__main__":
    main()
