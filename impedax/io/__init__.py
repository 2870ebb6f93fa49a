"""Reading and writing spectra: `load` recognises the file by content (see docs/io.md).

Layout: `loader` (`load`, `save`: detection and dispatch), `registry` (`Reader`), `table`
(tables with named columns), `csv` (delimited text), `netcdf` (impedax's lossless files), `export` (results as CSV tables, JSON, netCDF), `provenance` (what made a written result), `stack`
(`stack_files`: one spectrum per file as one series), and
``formats/`` — one module per instrument format, each documenting its sign and unit conventions,
and `READERS`/`register_reader`.
"""

from __future__ import annotations

from .export import result_table as result_table, write_result as write_result
from .csv import CSV_HEADER as CSV_HEADER, read_csv as read_csv, write_csv as write_csv
from .formats import READERS as READERS, register_reader as register_reader
from .formats.autolab import read_autolab as read_autolab
from .formats.biologic import read_biologic as read_biologic, read_biologic_text as read_biologic_text
from .formats.biologic_mpr import read_biologic_mpr as read_biologic_mpr
from .formats.chinstruments import read_chinstruments as read_chinstruments
from .formats.dfr import read_dfr as read_dfr
from .formats.gamry import read_gamry as read_gamry
from .formats.ivium import read_ivium as read_ivium
from .formats.labone_csv import read_labone_csv as read_labone_csv
from .formats.labone_hdf5 import read_labone_hdf5 as read_labone_hdf5
from .formats.palmsens import read_palmsens as read_palmsens
from .formats.parstat import read_parstat as read_parstat
from .formats.powersuite import read_powersuite as read_powersuite
from .formats.spreadsheet import read_spreadsheet as read_spreadsheet
from .formats.versastudio import read_versastudio as read_versastudio
from .formats.z60w import read_z60w as read_z60w
from .formats.zplot import read_zplot as read_zplot
from .loader import MAX_FILE_BYTES as MAX_FILE_BYTES, identify as identify, load as load, save as save
from .netcdf import read_netcdf as read_netcdf, write_netcdf as write_netcdf
from .registry import Reader as Reader
from .stack import stack_files as stack_files

__all__ = [
    "load", "save", "identify", "read_csv", "write_csv", "read_netcdf", "write_netcdf", "CSV_HEADER", "READERS", "Reader",
    "register_reader", "MAX_FILE_BYTES", "write_result", "result_table", "stack_files",
    "read_gamry", "read_biologic", "read_biologic_text", "read_biologic_mpr", "read_zplot", "read_z60w", "read_autolab",
    "read_dfr", "read_parstat", "read_powersuite", "read_chinstruments", "read_versastudio", "read_labone_csv",
    "read_labone_hdf5", "read_palmsens", "read_ivium", "read_spreadsheet",
]
