"""The bundled scenes, one TOML file each (`fsi scenes` lists them)."""
