"""Liquid models. Knows nothing of particles: takes points, returns pressure at them."""
