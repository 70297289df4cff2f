"""What a run leaves on disk: result.h5 and XDMF output, plots, checkpoints, results folders."""
