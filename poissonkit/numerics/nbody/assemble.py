"""One generator that assembles force terms into a system's kernels.

A **term** adds forces (and torques) to the scratch and returns its energy:
``term(data, work) -> U``, compiled twice (:class:`Term`: a separate function and one inlined
into the hot kick). The pair loop (listed pairs, all-pairs sets over cell or Verlet lists), the
lean direct sum and each kind of external field are terms. A **layout** (:class:`Layout`) says
how a family of systems stores its bodies: how to gather positions into the scratch, clear the
forces, push ``h`` times the forces into the momenta, write ``ẏ`` and add the kinetic energy.

:func:`assemble` writes the kernels of a sum of terms once, as source, and compiles it:

* ``forces``: clear, then every term adds to the same forces;
* ``rhs``: the first term's forces written as ``ẏ``, each further term cleared and added;
* ``kick`` / ``kick_compensated``: each term in turn cleared, evaluated and pushed (``r`` and
  ``ν`` are constant in a kick, so the kick of the sum is the kicks of the terms in turn); the
  two differ only in the ``add(y, c, i, v)`` the push uses
  (:func:`~poissonkit.numerics.kernels.plain_add` or
  :func:`~poissonkit.numerics.kernels.kahan_add`);
* ``energy``: the first term, the kinetic energy, then the further terms.

Adding a kind of term (a field, a constraint force) is writing its ``term(data, work)``; the
kernels around it come from here, the same for plain and compensated sums.

**Reference counts.** numba counts references to every array a kernel reads (an atomic
increment and decrement each time a function takes an array out of ``data`` or ``work``) and
prunes the pairs it can prove redundant. It cannot prune them across a call that may return an
error (a potential too large to be inlined, as most orientation-dependent ones are): then a
kick of two tops spends most of its time on reference counts (~55 atomic operations, about
three times the pair formula). A term that allocates no array (:attr:`Term.allocates` false:
the pair loops without cell or neighbour lists, the direct sum, the fields) needs no counts,
and when no term of a sum allocates, the kernels are compiled without them (numba's
``_nrt=False``): the same instructions for the arithmetic, so the same numbers bit for bit.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple, cast

from numba.core.dispatcher import Dispatcher

from poissonkit.numerics.jit import compile_generated, jit
from poissonkit.numerics.kernels import Kernels


class Term(NamedTuple):
    """One force term, ``term(data, work) -> U`` adding to ``work``'s forces (and torques)."""

    #: a separate compiled function (``rhs`` and ``energy`` call it)
    plain: Dispatcher
    #: the same, inlined into its callers (the hot kick and ``forces``)
    inline: Dispatcher
    #: whether it may allocate an array (a cell or neighbour list): then the kernels that
    #: call it keep numba's reference counts (see the module docstring)
    allocates: bool = True


class Layout(NamedTuple):
    """How a family of systems stores its bodies: the pieces the generated kernels call."""

    #: ``gather(y, data, work)``: positions (and axes) into ``work``
    gather: Dispatcher
    #: the same, inlined into the hot kick and ``forces``
    gather_inline: Dispatcher
    #: ``clear(data, work)``: forces (and torques) to zero
    clear: Dispatcher
    #: ``push(y, c, h, data, work)``: momenta += ``h`` forces, through ``plain_add``
    push_plain: Dispatcher
    #: the same through ``kahan_add``
    push_compensated: Dispatcher
    #: ``rhs_write(y, data, work, out)``: ``out = ẏ`` with the forces in ``work``
    rhs_write: Dispatcher
    #: ``kinetic(y, data, e) -> e + kinetic energy``
    kinetic: Dispatcher
    #: the potential-free kernels
    drift: Dispatcher
    drift_compensated: Dispatcher
    min_distance: Dispatcher
    max_radius: Dispatcher
    #: whether ``kick`` is inlined into the time loops that call it
    inline_kick: bool


def _source(n_terms: int) -> str:
    """The kernels of ``n_terms`` terms ``t0 .. t{n-1}`` (``t0_i``: inlined), as source."""
    ks = range(n_terms)
    lines = ["def forces(y, data, work):",
             "    gather_i(y, data, work)",
             "    clear(data, work)",
             "    u = t0_i(data, work)"]
    lines += [f"    u = u + t{k}_i(data, work)" for k in ks if k]
    lines += ["    return u", "",
              "def rhs(y, data, work, out):",
              "    gather(y, data, work)",
              "    clear(data, work)",
              "    t0(data, work)",
              "    rhs_write(y, data, work, out)"]
    for k in ks:
        if k:
            lines += ["    clear(data, work)", f"    t{k}(data, work)",
                      "    push_plain(out, out, 1.0, data, work)"]  # 1.0 * F is exact
    lines += ["", "def energy(y, data, work):",
              "    gather(y, data, work)",
              "    clear(data, work)",
              "    e = t0(data, work)",
              "    e = kinetic(y, data, e)"]
    for k in ks:
        if k:
            lines += ["    clear(data, work)", f"    e = e + t{k}(data, work)"]
    lines += ["    return e"]
    for name, args, c, push in (("kick", "y, h, data, work", "y", "push_plain"),
                                ("kick_compensated", "y, c, h, data, work", "c",
                                 "push_compensated")):
        lines += ["", f"def {name}({args}):", "    gather_i(y, data, work)"]
        for k in ks:
            lines += ["    clear(data, work)", f"    t{k}_i(data, work)",
                      f"    {push}(y, {c}, h, data, work)"]
    return "\n".join(lines) + "\n"


#: id of a term's plain dispatcher -> (its compilation without reference counts, the original)
_uncounted: dict[int, tuple[Dispatcher, Dispatcher]] = {}


def _without_counts(plain: Dispatcher) -> Dispatcher:
    """``plain`` compiled again without reference counts (its own options otherwise): the
    separately compiled term that ``rhs`` and ``energy`` call counts its own references."""
    hit = _uncounted.get(id(plain))
    if hit is None:
        opts = {k: v for k, v in plain.targetoptions.items()
                if k in ("error_model", "inline", "fastmath", "boundscheck")}
        hit = _uncounted[id(plain)] = (jit(**opts, _nrt=False)(plain.py_func), plain)
    return hit[0]


#: (layout, terms, counted) -> kernels; the key holds the dispatchers, so their ids stay unique
_cache: dict[tuple[int, ...], tuple[Kernels, tuple[object, ...]]] = {}


def assemble(layout: Layout, terms: Sequence[Term], counted: bool | None = None) -> Kernels:
    """The kernels of the sum of ``terms`` on ``layout`` (cached; see the module docstring).

    Every kernel is compiled from one generated source through
    :func:`~poissonkit.numerics.jit.compile_generated`, so it is kept in the disk cache.
    ``counted``: compile with numba's reference counts; ``None`` (default) keeps them only when
    some term allocates (:attr:`Term.allocates`). ``True`` gives the kernels as they were
    before the counts were dropped (a benchmark's baseline); the numbers are the same.
    """
    if not terms:
        raise ValueError("assemble needs at least one force term")
    if counted is None:
        counted = any(t.allocates for t in terms)
    keep = (layout, *terms)
    key = (*(id(v) for v in keep), int(counted))
    hit = _cache.get(key)
    if hit is not None:
        return hit[0]
    source = _source(len(terms))
    ns: dict[str, object] = {name: getattr(layout, name) for name in (
        "clear", "push_plain", "push_compensated", "rhs_write", "kinetic", "gather")}
    ns["gather_i"] = layout.gather_inline
    for k, t in enumerate(terms):
        # mypy reads a Dispatcher field through Dispatcher.__get__ (a method binder) as a method
        plain = cast(Dispatcher, t.plain)
        ns[f"t{k}"] = plain if counted else _without_counts(plain)
        ns[f"t{k}_i"] = t.inline

    def build(name: str, **options: object) -> Dispatcher:
        if not counted:  # no term allocates: no reference counts (module docstring)
            options["_nrt"] = False
        return compile_generated(source, name, ns, **options)

    kick_opts = {"inline": "always"} if layout.inline_kick else {}
    out = Kernels(rhs=build("rhs"), drift=layout.drift,
                  kick=build("kick", **kick_opts), energy=build("energy"),
                  min_distance=layout.min_distance, max_radius=layout.max_radius, jac=None,
                  splittable=True, forces=build("forces", inline="always"),
                  drift_compensated=layout.drift_compensated,
                  kick_compensated=build("kick_compensated", **kick_opts))
    _cache[key] = (out, keep)
    return out
