"""The package version, in a module of its own so any layer can stamp it without importing the API."""

__version__ = "0.1.0"


def stamp(schema: str) -> dict:
    """The head of every result document springcad writes (``design.json``, ``fea.json``,
    ``build.json``, ``fit.json``, ``synthesis.json``, ``explore.json``,
    ``validation.json``): its schema and the version that wrote it, stamped here only."""
    return {"schema": schema, "springcad_version": __version__}
