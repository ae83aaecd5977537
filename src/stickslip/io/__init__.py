"""Input and output: CSV files with units in the header."""

from .csv import write_columns

__all__ = ["write_columns"]
