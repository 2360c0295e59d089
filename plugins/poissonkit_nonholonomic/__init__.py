"""Built-in poissonkit plugin: nonholonomic."""
