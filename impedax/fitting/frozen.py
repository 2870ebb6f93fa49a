"""What a frozen result holds, made read-only (docs/fitting.md, "Results are read-only").

A frozen dataclass refuses ``result.values = ...`` but not ``result.values["R0"] = 1`` nor
``c = batch.values("C"); c *= 1e9``, which changed the result (and every report, derived
quantity and file written from it afterwards) silently. As NumPy and xarray do for memory
that must not change, a result's arrays carry NumPy's read-only flag (a write raises
``ValueError: assignment destination is read-only``), its mappings refuse item assignment,
and ``to_xarray`` hands out a copy the user may edit. The result takes its own copy of what
it is given, so the caller's arrays (the data's ``Z``) stay writable.
"""

from __future__ import annotations

import copy
import dataclasses
import difflib

import jax
import numpy as np
import xarray as xr

__all__ = ["FrozenResult", "ReadOnlyDict", "KeyHintDict", "MissingKey", "freeze_fields", "read_only", "read_only_array", "read_only_dataset"]


class MissingKey(KeyError):
    """The KeyError of a result's mapping (``fit.values["R_1"]``): ``args[0]`` is the key, as a
    KeyError's (code that reads it is unchanged), and its text names the closest key and the keys
    there are, where a plain KeyError said ``'R_1'`` alone. The closest key: the key but for case
    (``r1``: ``R1``), else one the key begins (``CPE1.a``: ``CPE1.alpha``; a joint posterior's ``R1``: ``R1[cell=a]``), else one that names
    it in brackets (a hierarchical posterior's ``ess()["R1"]``: ``mu[R1]``), else difflib's."""

    def __init__(self, key, known):
        super().__init__(key)
        self.known = tuple(known)

    def __str__(self) -> str:
        key = self.args[0]
        names = [str(k) for k in self.known]
        typed = str(key)
        close = ([n for n in names if n.casefold() == typed.casefold()] or [n for n in names if n.startswith(typed)] or [n for n in names if n.endswith(f"[{typed}]")]
                 or difflib.get_close_matches(typed, names, n=1))  # ('r1': R1; 'CPE1.a': CPE1.alpha; 'R1': mu[R1])
        hint = f"; did you mean {close[0]!r}?" if close else ""
        listed = ", ".join(names[:12]) + (", …" if len(names) > 12 else "")
        return f"{key!r}{hint} (the keys: {listed or 'none'})"


class KeyHintDict(dict):
    """A dict, editable, whose missing key raises `MissingKey` (the closest key and the keys
    there are) where a dict's said ``'R9'`` alone: what a result computes on request and hands
    over to edit (a posterior's ``samples``). A JAX pytree with the leaves of the equal dict, in
    the same order; ``json.dumps``, ``pickle`` and ``copy`` work as on a dict."""

    def __missing__(self, key):
        raise MissingKey(key, self)


class ReadOnlyDict(KeyHintDict):
    """A dict that refuses to change: item assignment, deletion, ``update``, ``pop``, ``|=``
    and the like raise TypeError (as ``types.MappingProxyType``). Unlike a mapping proxy it is
    still a dict, so ``json.dumps``, ``pickle``, ``copy`` and ``dict(d)`` (an editable copy)
    work as before, and a JAX pytree (`jax.tree_util`, ``jit`` arguments) with the leaves of
    the equal dict, in the same order. A missing key raises `MissingKey` (`KeyHintDict`)."""

    def _refuse(self, *args, **kwargs):
        raise TypeError("a result's mapping is read-only: dict(...) gives an editable copy")

    __setitem__ = __delitem__ = __ior__ = clear = pop = popitem = setdefault = update = _refuse

    def __reduce__(self):
        return (ReadOnlyDict, (dict(self),))

    def __copy__(self):
        return self

    def __deepcopy__(self, memo):
        return ReadOnlyDict(copy.deepcopy(dict(self), memo))


def _flatten(mapping: KeyHintDict):
    keys = sorted(mapping)  # (a dict's leaf order: `jax.tree_util` sorts its keys)
    return [mapping[k] for k in keys], (tuple(keys), tuple(mapping))


def _unflattener(kind: type[KeyHintDict]):
    def unflatten(aux, leaves) -> KeyHintDict:
        sorted_keys, order = aux
        by_key = dict(zip(sorted_keys, leaves))
        return kind((k, by_key[k]) for k in order)

    return unflatten


for _kind in (KeyHintDict, ReadOnlyDict):
    jax.tree_util.register_pytree_node(_kind, _flatten, _unflattener(_kind))


def read_only_array(array) -> np.ndarray:
    """A read-only copy of ``array`` (itself if it is a NumPy array already read-only and owning its memory)."""
    if isinstance(array, np.ndarray) and not array.flags.writeable and array.base is None:
        return array
    out = np.array(array)
    out.flags.writeable = False
    return out


def read_only_dataset(ds: xr.Dataset) -> xr.Dataset:
    """A copy of ``ds`` whose arrays are read-only (loaded from a file or dask if lazy) and
    whose attributes are its own (deep-copied); the index coordinates xarray keeps immutable
    already. ``ds`` itself is left as it was."""
    out = ds.copy(deep=False)
    for variable in out.variables.values():
        if not isinstance(variable, xr.IndexVariable):
            variable.data = read_only_array(variable.values)
    out.attrs = copy.deepcopy(ds.attrs)
    return out


def read_only_data_array(da: xr.DataArray) -> xr.DataArray:
    """A copy of ``da`` whose array and coordinates' arrays are read-only (`read_only_dataset`)."""
    out = da.copy(deep=False)
    for variable in (out.variable, *(out.coords[name].variable for name in out.coords)):
        if not isinstance(variable, xr.IndexVariable):  # (an index coordinate, or a DataArray that is one, is immutable)
            variable.data = read_only_array(variable.values)
    out.attrs = copy.deepcopy(da.attrs)
    return out


def read_only(value):
    """``value`` as a result keeps it: a NumPy array as a read-only copy, an xarray Dataset or
    DataArray as one with read-only arrays, a dict as a `ReadOnlyDict` of read-only values, a
    tuple as a tuple of read-only items; anything else (numbers, text, JAX arrays, circuits,
    other frozen results) as it is."""
    if isinstance(value, np.ndarray):
        return read_only_array(value)
    if isinstance(value, xr.Dataset):
        return read_only_dataset(value)
    if isinstance(value, xr.DataArray):
        return read_only_data_array(value)
    if type(value) is ReadOnlyDict and getattr(value, "_values_read_only", False):
        return value  # (made here before: its values are read-only already, and it refuses change)
    if type(value) in (dict, KeyHintDict, ReadOnlyDict):
        out = ReadOnlyDict((k, read_only(v)) for k, v in value.items())
        out._values_read_only = True  # (a 1,000-spectrum batch's warnings and tags took 9 ms to walk again in each copy of the result)
        return out
    if type(value) is tuple and any(isinstance(v, (np.ndarray, dict, tuple, xr.Dataset, xr.DataArray)) for v in value):
        return tuple(read_only(v) for v in value)
    return value


class FrozenResult:
    """Base of the results whose ``__post_init__`` calls `freeze_fields`: a copy made by pickle
    or ``copy.deepcopy``, which rebuild NumPy arrays writable and skip ``__post_init__``, is
    made read-only again (a pickled fit's ``z_data[0] = 0`` changed its report, 2026-12-06)."""

    def __setstate__(self, state) -> None:
        self.__dict__.update(state)
        freeze_fields(self)


def freeze_fields(result) -> None:
    """Make every field of the frozen dataclass instance ``result`` read-only (`read_only`),
    from its ``__post_init__``: what the constructor was given is copied, never frozen in place."""
    for f in dataclasses.fields(result):
        object.__setattr__(result, f.name, read_only(getattr(result, f.name)))
