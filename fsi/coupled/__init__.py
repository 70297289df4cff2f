"""The membrane and the liquid as coupling participants: adapters, pressure maps, window control."""
