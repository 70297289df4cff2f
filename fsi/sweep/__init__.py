"""Sweeps: sweep files, cases run on Dask, the combined xarray dataset and its plots."""
