"""Built-in poissonkit plugin: nbody."""
