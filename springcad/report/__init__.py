"""Reports, plots and file writing (the only layer besides the CLI that writes files)."""
