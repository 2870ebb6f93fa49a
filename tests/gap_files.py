"""Test helper: the three spectra of a gap analysis written as netCDF files, for the CLI."""

import impedax as ix


def saved_gap_files(folder, datasets) -> list[str]:
    """``datasets`` (total, skin, touchscreen) saved as ``total.nc``, ``skin.nc``, ``ts.nc`` in
    ``folder``; their paths in the order ``impedax gap`` takes them."""
    paths = []
    for name, ds in zip(("total", "skin", "ts"), datasets):
        paths.append(str(folder / f"{name}.nc"))
        ix.save(ds, paths[-1])
    return paths
