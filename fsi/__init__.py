"""The application: scenes, runner, output, analysis, plots and CLI."""
