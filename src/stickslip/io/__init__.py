"""Input and output: the files stickslip reads and writes, with their units and without loss.

* :mod:`.records`, :mod:`.formats`, :mod:`.text`, :mod:`.tables`: measured force-time records
  and the files laboratories write (MATLAB, HDF5, NumPy, Excel, TDMS, delimited text);
* :mod:`.lab`: rate-and-state laboratory records and load-point histories;
* :mod:`.csv`, :mod:`.netcdf`, :mod:`.jsonable`: tables with units in the header, datasets as
  NetCDF or CSV, JSON without ``NaN``;
* :mod:`.output`: atomic files, own-file recognition, staged output folders;
* :mod:`.errors`: :class:`~.errors.DataError` and its kinds.
"""

from .csv import write_columns
from .netcdf import load_dataset, save_dataset

__all__ = ["load_dataset", "save_dataset", "write_columns"]
