"""epaphe: read Epaphe runs, edit decks, run studies, measure and plot (docs/user/python.md).

    import epaphe
    run = epaphe.open("build/run/bar-on-wall.h5")       # an epaphe.results.Run
    f = run.bodies["Bar"].contact.total_force             # N, one value per record
    t = run.time                                          # s

Modules: results (the HDF5 reader), deck (decks with line numbers, overrides), schema (the valid
deck parameters from `epaphe-run --print-parameters=xml`), measures (contact events, spectra,
engine orders, study measures and errors), exact (exact solutions of the verification cases),
plots (figures; imports matplotlib), study and runner (epaphe-sweep's studies), cli (the command
lines). `import epaphe` needs numpy and h5py only, and imports them on first use: the names below
are loaded when first touched.
"""

_EXPORTS = {
    "open": ("results", "open"),
    "Run": ("results", "Run"),
    "history": ("results", "history"),
    "Deck": ("deck", "Deck"),
    "read_deck": ("deck", "read_deck"),
    "deck_value": ("deck", "deck_value"),
    "variant": ("deck", "variant"),
    "Schema": ("schema", "Schema"),
    "find_run": ("runner", "find_run"),
    "EpapheError": ("errors", "EpapheError"),
}

__all__ = sorted(_EXPORTS)


def __getattr__(name):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'epaphe' has no attribute '{name}'")
    import importlib

    module, attr = _EXPORTS[name]
    value = getattr(importlib.import_module(f"{__name__}.{module}"), attr)
    globals()[name] = value
    return value


def __dir__():
    return sorted(list(globals()) + list(_EXPORTS))
