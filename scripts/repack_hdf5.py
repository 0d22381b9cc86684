"""Repack an HDF5 file (a .cool / .mcool) with HDF5 1.10's compact object headers and gzip 9.

data/ is kept under 10 MB; small coolers written by cooler spend most of their bytes on HDF5's
default object headers. Every group, dataset (values and dtype, the chromosome enum included)
and attribute is copied unchanged; only the storage layout differs.

    .venv-python/bin/python scripts/repack_hdf5.py IN.cool OUT.cool   (any Python with h5py)
"""

import sys

import h5py


def repack(source, path):
    """Copies every group, dataset and attribute of `source` into a new `path` written with
    `libver=("v110", "latest")`, datasets gzip-compressed (level 9, shuffled)."""
    gz = {"compression": "gzip", "compression_opts": 9, "shuffle": True}
    with h5py.File(source, "r") as src, h5py.File(path, "w", libver=("v110", "latest")) as dst:
        dst.attrs.update(src.attrs)

        def copy(name, item):
            if isinstance(item, h5py.Group):
                dst.require_group(name).attrs.update(item.attrs)
            else:
                data = dst.create_dataset(name, data=item[()], dtype=item.dtype, **gz)
                data.attrs.update(item.attrs)

        src.visititems(copy)


if __name__ == "__main__":
    repack(sys.argv[1], sys.argv[2])
