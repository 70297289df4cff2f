"""The bundled sweeps, one TOML file each (`fsi sweeps` lists them)."""
