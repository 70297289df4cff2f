"""Model problems shared by the tests and the benchmarks: each with its closed form or published reference."""
