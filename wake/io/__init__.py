"""Real data in: recordings from CSV, PADS and MATLAB files onto a uniform grid; results out with names and units.

>>> from wake.io import read_recording          # doctest: +SKIP
>>> rec = read_recording("019_DrinkGlas_RightWrist.txt")   # doctest: +SKIP
>>> rec.fs, rec.channels, rec.timing.resampled             # doctest: +SKIP
(100.0, ('acc_x', 'acc_y', 'acc_z', 'gyro_x', 'gyro_y', 'gyro_z'), True)

The streams of ``wake stream`` (live data over pipes or Lab Streaming Layer)
are in :mod:`wake.io.stream`; the command's options in :mod:`wake.cli`.
"""

from wake.io.readers import FORMATS, PADS_CHANNELS, PADS_UNITS, read_csv, read_pads, read_recording
from wake.io.matlab import read_mat
from wake.io.recording import Recording, Timing, analyse_time, nominal_rate, resample_uniform
from wake.io.writers import result_columns, write_result_csv, write_tremor_csv

__all__ = ["FORMATS", "PADS_CHANNELS", "PADS_UNITS", "Recording", "Timing", "analyse_time", "nominal_rate",
           "read_csv", "read_mat", "read_pads", "read_recording", "resample_uniform", "result_columns",
           "write_result_csv", "write_tremor_csv"]
