"""Built-in poissonkit plugin: magnets."""
