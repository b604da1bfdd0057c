"""Scripts that run inside the DEM engines (YADE's own Python), shipped with dtcrit and never imported by it."""
