"""``NumPoissonGeometry``: vectorised drop-in for ``numericalpoissongeometry`` (1.1.2) mesh methods.

NumericalPoissonGeometry evaluates its ``num_*`` methods point by point: a ``lambdify``-ed
function is called once per mesh point from a Python loop and the results are multiplied with
``np.dot`` one point at a time. Here each method derives the symbolic result once (with
:class:`poissonkit.compat.PoissonGeometry`, so the same formulas and the same signs), compiles it
with ``sympy.lambdify(..., cse=True)`` and evaluates it on the whole mesh in one vectorised numpy
call. Compiled functions are cached per input, so a second call on another mesh costs only the
numpy evaluation.

Shapes are NumericalPoissonGeometry's: ``(N, n, n)`` for bivectors / 2-forms, ``(N, n, 1)`` for
vector fields and 1-forms, ``(N,)`` for functions, ``(N, n, .., n)`` (fully antisymmetric) for
``k``-vectors with ``k >= 2``; ``dict_output=True`` gives a numpy array of per-point dicts.
Arrays are computed component by component and returned as point-major *views* of that
storage (``np.moveaxis``), so they are not C-contiguous; call ``np.ascontiguousarray`` if a
consumer needs that.
``torch_output`` / ``tf_output`` convert with PyTorch / TensorFlow when installed.

Signs: ``num_hamiltonian_vf`` and ``num_sharp_morphism`` use PoissonGeometry's
``X_h = {h, .} = -P dh`` — the opposite of poissonkit's ``P dH`` (:mod:`poissonkit.conventions`).
The curl / modular vector field use the corrected density derivative (docs/compat.md).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from itertools import permutations

import numpy as np
import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import PRECEDENCE

from poissonkit.compat import _calculus as calc
from poissonkit.compat._inputs import Key, is_zero, validate_dimension
from poissonkit.compat.errors import CasimirError, FunctionError
from poissonkit.compat.symbolic import PoissonGeometry
from poissonkit.errors import DimensionError, InputError, MissingDependencyError

Dict = Mapping[tuple[int, ...], object]
#: Most compiled evaluators kept per instance (inputs beyond that are recompiled).
CACHE_SIZE: int = 256
#: Total operation count above which the compiled code eliminates common subexpressions.
CSE_MIN_OPS: int = 60


def _freeze(obj: object) -> object:
    """A hashable stand-in for an input (dicts, lists, strings, numbers, sympy objects)."""
    if isinstance(obj, Mapping):
        return ("dict", tuple(sorted((repr(k), _freeze(v)) for k, v in obj.items())))
    if isinstance(obj, (list, tuple)):
        return ("seq", tuple(_freeze(v) for v in obj))
    return (type(obj).__name__, str(obj))


def _parity(perm: Sequence[int]) -> int:
    inversions = sum(1 for a in range(len(perm)) for b in range(a + 1, len(perm)) if perm[a] > perm[b])
    return -1 if inversions % 2 else 1


class _Printer(NumPyPrinter):
    """NumPy printer that writes small integer powers as products.

    sympy prints ``b**-2`` as ``b**(-2.0)``; libm's ``pow`` with a negative base takes a slow path
    (about 50x slower than a product), so ``(x1 - x2)**(-2)`` dominated the evaluation.
    """

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 1 <= abs(int(exp)) <= 8:
            b = self.parenthesize(base, PRECEDENCE["Mul"], strict=True)
            prod = "*".join([b] * abs(int(exp)))
            return f"({prod})" if exp > 0 else f"(1/({prod}))"
        return super()._print_Pow(expr, rational=rational)


class _Evaluator:
    """``exprs`` compiled once; ``__call__(mesh) -> (len(exprs), N)`` float array.

    Component-major: every output row is written contiguously (writing columns of an
    ``(N, k)`` array is strided and cost more than the arithmetic).
    """

    def __init__(self, exprs: Sequence[sp.Expr], coords: Sequence[sp.Symbol]) -> None:
        exprs = [sp.sympify(e) for e in exprs]
        free = set().union(*(e.free_symbols for e in exprs)) - set(coords) if exprs else set()
        if free:
            raise InputError("cannot evaluate on a mesh: free parameters "
                             f"{sorted(map(str, free))}; substitute numbers for them first")
        self.size = len(exprs)
        # common subexpressions pay off on big results; on a few small ones cse costs more
        # (in compile time) than it saves
        use_cse = sum(sp.count_ops(e) for e in exprs) > CSE_MIN_OPS
        self._f: Callable = sp.lambdify(list(coords), exprs, modules="numpy", cse=use_cse,
                                        printer=_Printer({"fully_qualified_modules": False,
                                                          "inline": True,
                                                          "allow_unknown_functions": True,
                                                          "user_functions": {}}))

    def __call__(self, mesh: np.ndarray) -> np.ndarray:
        n_points = mesh.shape[0]
        out = np.empty((self.size, n_points))
        if self.size == 0:
            return out
        columns = np.ascontiguousarray(mesh.T)  # strided columns are ~3x slower
        with np.errstate(all="ignore"):  # reported below instead of as warnings
            values = self._f(*columns)
        for c, v in enumerate(values):
            out[c] = v  # constant entries come back as scalars and broadcast here
        return out


class NumPoissonGeometry:
    """Vectorised mesh evaluation in NumericalPoissonGeometry's formats.

    Parameters
    ----------
    dimension
        ``n >= 2``.
    variable
        Coordinate prefix (default ``x``: coordinates ``x1 .. xn``).

    Attributes
    ----------
    dim, variable, coords
        As in NumericalPoissonGeometry.
    pg
        The symbolic :class:`~poissonkit.compat.PoissonGeometry` used for derivations.

    Notes
    -----
    A mesh is an array of shape ``(N, n)`` (one point per row) of finite values (a NaN or
    infinite coordinate is an :class:`~poissonkit.errors.InputError`). Points where a result is not
    finite (division by zero, ``log`` of a negative number) are reported with
    :class:`~poissonkit.errors.InputError` naming the first such point, never returned as NaN.

    Examples
    --------
    >>> import numpy as np
    >>> from poissonkit.compat import NumPoissonGeometry
    >>> npg = NumPoissonGeometry(3)
    >>> P = {(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}
    >>> npg.num_hamiltonian_vf(P, "1/(x1 - x2) + 1/(x1 - x3) + 1/(x2 - x3)",
    ...                        np.array([[1.0, 2.0, 3.0]]))[0, :, 0]
    array([ 2.5, -5. ,  2.5])
    """

    def __init__(self, dimension: int, variable: str = "x") -> None:
        self.dim = validate_dimension(dimension)
        self.variable = variable
        self.pg = PoissonGeometry(self.dim, variable)
        self.coords = self.pg.coords
        self._reader = self.pg._reader
        self._cache: dict[object, object] = {}

    def __repr__(self) -> str:
        return f"NumPoissonGeometry({self.dim}, variable={self.variable!r})"

    # ------------------------------------------------------------------ plumbing
    def _mesh(self, mesh: object) -> np.ndarray:
        try:
            arr = np.asarray(mesh, dtype=float)
        except (TypeError, ValueError):
            raise InputError("mesh must be a numeric array of shape (N, dim)") from None
        if arr.ndim != 2 or arr.shape[1] != self.dim:
            raise DimensionError(f"mesh must have shape (N, {self.dim}), got {arr.shape}")
        bad = ~np.isfinite(arr).all(axis=1)
        if bad.any():  # checked up front: a NaN point would otherwise come back as NaN output
            k = int(np.argmax(bad))
            raise InputError(f"mesh is not finite at {int(bad.sum())} point(s), first at "
                             f"row {k}: {arr[k].tolist()}")
        return arr

    def _cached(self, key: object, build: Callable[[], object]) -> object:
        try:
            return self._cache[key]
        except KeyError:
            pass
        value = build()
        if len(self._cache) >= CACHE_SIZE:
            self._cache.pop(next(iter(self._cache)))
        self._cache[key] = value
        return value

    def _evaluate(self, ev: _Evaluator, mesh: np.ndarray, what: str) -> np.ndarray:
        values = ev(mesh)
        bad = ~np.isfinite(values).all(axis=0)
        if bad.any():  # the mesh itself is finite (checked by _mesh)
            k = int(np.argmax(bad))
            raise InputError(f"{what} is not finite at {int(bad.sum())} mesh point(s), first at "
                             f"row {k}: {mesh[k].tolist()}")
        return values

    def _components(self, tag: str, args: tuple, derive: Callable[[], dict[Key, sp.Expr]]):
        """``(keys, evaluator)`` for a symbolic result ``{0-based key: expr}``, cached."""
        def build():
            comps = derive()
            keys = list(comps)
            return keys, _Evaluator([comps[k] for k in keys], self.coords)
        return self._cached((tag, _freeze(args)), build)

    @staticmethod
    def _convert(result, torch_output: bool, tf_output: bool):
        if torch_output:
            try:
                import torch
            except ImportError:
                raise MissingDependencyError("torch_output needs PyTorch: pip install torch") from None
            return torch.from_numpy(result)
        if tf_output:
            try:
                import tensorflow as tf
            except ImportError:
                raise MissingDependencyError(
                    "tf_output needs TensorFlow: pip install tensorflow") from None
            return tf.convert_to_tensor(result)
        return result

    def _tensor(self, keys: Sequence[Key], values: np.ndarray, degree: int) -> np.ndarray:
        """Fully antisymmetric array ``(N,) + shape`` from sorted 0-based keys (PoissonGeometry's
        shapes: ``()`` for degree 0, ``(n, 1)`` for degree 1, ``(n,)*k`` otherwise)."""
        n_points, n = values.shape[1], self.dim
        if degree == 1 and list(keys) == [(i,) for i in range(n)]:
            # the evaluator's (n, N) rows already are the field: no copy, a transposed view
            return np.moveaxis(values[:, None, :], -1, 0)
        shape = () if degree == 0 else (n, 1) if degree == 1 else (n,) * degree
        out = np.zeros(shape + (n_points,))  # component-major, viewed point-major at the end
        for c, key in enumerate(keys):
            if degree == 0:
                out += values[c]
            elif degree == 1:
                out[key[0], 0] += values[c]
            else:
                for perm in permutations(range(degree)):
                    out[tuple(key[p] for p in perm)] += _parity(perm) * values[c]
        return np.moveaxis(out, -1, 0)

    @staticmethod
    def _dicts(keys: Sequence[Key], values: np.ndarray, all_orders: bool = False) -> np.ndarray:
        """Per-point dicts ``{1-based key: value}`` of the non-zero values (object array)."""
        values = values.T  # one row per point
        result = np.empty(values.shape[0], dtype=object)
        expanded = []
        for c, key in enumerate(keys):
            orders = permutations(range(len(key))) if all_orders else [tuple(range(len(key)))]
            expanded.extend((tuple(key[p] + 1 for p in perm), _parity(perm), c) for perm in orders)
        for r in range(values.shape[0]):
            row = values[r]
            result[r] = {k: float(s * row[c]) for k, s, c in expanded if row[c] != 0}
        return result

    def _bivector_components(self, bivector: Dict) -> dict[Key, sp.Expr]:
        P = self.pg._P(bivector)
        n = self.dim
        return {(i, j): P.matrix[i, j] for i in range(n) for j in range(i + 1, n)
                if P.matrix[i, j] != 0}

    def _matrices(self, tag: str, args: tuple, derive, mesh) -> tuple[list[Key], np.ndarray]:
        keys, ev = self._components(tag, args, derive)
        return keys, self._evaluate(ev, mesh, tag)

    # ------------------------------------------------------------------ bivectors
    def num_bivector(self, bivector: Dict, mesh, torch_output: bool = False,
                     tf_output: bool = False, dict_output: bool = False):
        """A bivector on every mesh point: ``(N, n, n)`` matrices, or per-point dicts."""
        mesh = self._mesh(mesh)
        keys, vals = self._matrices("bivector", (bivector,),
                                    lambda: self._bivector_components(bivector), mesh)
        if dict_output:
            return self._dicts(keys, vals)
        return self._convert(self._tensor(keys, vals, 2), torch_output, tf_output)

    def num_bivector_to_matrix(self, bivector: Dict, mesh, torch_output: bool = False,
                               tf_output: bool = False):
        """Matrix of a bivector on every mesh point, shape ``(N, n, n)``."""
        return self.num_bivector(bivector, mesh, torch_output, tf_output)

    def _vector(self, tag: str, args: tuple, column: Callable[[], sp.MatrixBase], mesh,
                torch_output: bool, tf_output: bool, dict_output: bool):
        mesh = self._mesh(mesh)

        def derive():
            col = column()
            return {(i,): col[i] for i in range(self.dim)}

        keys, vals = self._matrices(tag, args, derive, mesh)
        if dict_output:
            return self._dicts(keys, vals)
        return self._convert(self._tensor(keys, vals, 1), torch_output, tf_output)

    def num_sharp_morphism(self, bivector: Dict, one_form: Dict, mesh, torch_output: bool = False,
                           tf_output: bool = False, dict_output: bool = False):
        """``P#(alpha) = -P alpha`` (PoissonGeometry's sign) on every point, shape ``(N, n, 1)``."""
        return self._vector(
            "sharp", (bivector, one_form),
            lambda: calc.sharp(self.pg._P(bivector).matrix, self._reader.one_form(one_form)),
            mesh, torch_output, tf_output, dict_output)

    def num_hamiltonian_vf(self, bivector: Dict, function: object, mesh, torch_output: bool = False,
                           tf_output: bool = False, dict_output: bool = False):
        """``X_h = {h, .} = -P dh`` (PoissonGeometry's sign, minus poissonkit's) on every point.

        Returns
        -------
        numpy.ndarray
            Shape ``(N, n, 1)`` (or per-point dicts with ``dict_output``).
        """
        def column():
            h = self._reader.expr(function, "function")
            return calc.sharp(self.pg._P(bivector).matrix, self._reader.gradient(h))

        return self._vector("hamiltonian_vf", (bivector, function), column, mesh,
                            torch_output, tf_output, dict_output)

    def num_poisson_bracket(self, bivector: Dict, function_1: object, function_2: object, mesh,
                            torch_output: bool = False, tf_output: bool = False):
        """``{f, g} = df . P . dg`` on every point, shape ``(N,)``."""
        mesh = self._mesh(mesh)

        def derive():
            P = self.pg._P(bivector)
            f = self._reader.expr(function_1, "function_1")
            g = self._reader.expr(function_2, "function_2")
            return {(): P.bracket(f, g)}

        keys, vals = self._matrices("poisson_bracket", (bivector, function_1, function_2),
                                    derive, mesh)
        return self._convert(vals[0].copy(), torch_output, tf_output)

    # ------------------------------------------------------------------ divergence
    def _empty(self, torch_output: bool, tf_output: bool, dict_output: bool):
        if dict_output:
            return np.array({})
        return self._convert(np.array([]), torch_output, tf_output)

    def num_curl_operator(self, multivector: Dict, function: object, mesh,
                          torch_output: bool = False, tf_output: bool = False,
                          dict_output: bool = False):
        """Divergence of a multivector relative to ``f dx1^..^dxn`` (corrected, see
        :meth:`PoissonGeometry.curl_operator`) on every point.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` for a vector field, ``(N, n, 1)`` for a bivector, ``(N, n, .., n)`` above;
            an empty array for an empty multivector (as NumericalPoissonGeometry).
        """
        mesh = self._mesh(mesh)
        f = self._reader.expr(function, "function")
        if is_zero(f):
            raise FunctionError(f"function {function} == 0")
        if not multivector or isinstance(multivector, str):
            return self._empty(torch_output, tf_output, dict_output)
        A = self._reader.multivector(multivector)

        def derive():
            return calc.curl(dict(A.components), self.coords, f)

        keys, vals = self._matrices("curl", (multivector, function), derive, mesh)
        if not keys:
            return self._empty(torch_output, tf_output, dict_output)
        if dict_output:
            return self._dicts(keys, vals, all_orders=True)
        return self._convert(self._tensor(keys, vals, A.degree - 1), torch_output, tf_output)

    def num_modular_vf(self, bivector: Dict, function: object, mesh, torch_output: bool = False,
                       tf_output: bool = False, dict_output: bool = False):
        """Modular vector field relative to ``f dx1^..^dxn`` on every point, ``(N, n, 1)``."""
        minus_P = {(i + 1, j + 1): -v for (i, j), v in self._bivector_components(bivector).items()}
        if not minus_P:
            mesh = self._mesh(mesh)
            return self._convert(np.zeros((mesh.shape[0], self.dim, 1)), torch_output, tf_output)
        return self.num_curl_operator(minus_P, function, mesh, torch_output, tf_output, dict_output)

    # ------------------------------------------------------------------ Schouten calculus
    def num_coboundary_operator(self, bivector: Dict, multivector: Dict | str, mesh,
                                torch_output: bool = False, tf_output: bool = False,
                                dict_output: bool = False):
        """``[P, A]`` on every point: ``(N, n, .., n)`` fully antisymmetric (``k + 1`` indices).

        For a function (string) ``[P, f] = P df``, shape ``(N, n, 1)``. Empty array when the
        result vanishes identically (as NumericalPoissonGeometry).
        """
        from poissonkit.structure.schouten import lichnerowicz

        mesh = self._mesh(mesh)
        if not bivector or not multivector:
            return self._empty(torch_output, tf_output, dict_output)
        if isinstance(multivector, str):
            return self._vector(
                "coboundary_f", (bivector, multivector),
                lambda: self.pg._P(bivector).matrix * self._reader.gradient(
                    self._reader.expr(multivector, "multivector")),
                mesh, torch_output, tf_output, dict_output)
        A = self._reader.multivector(multivector)
        if A.degree + 1 > self.dim:
            return self._empty(torch_output, tf_output, dict_output)

        def derive():
            R = lichnerowicz(self.pg._P(bivector), A)
            return {k: v for k, v in R.components.items() if not is_zero(v)}

        keys, vals = self._matrices("coboundary", (bivector, multivector), derive, mesh)
        if not keys:
            return self._empty(torch_output, tf_output, dict_output)
        if dict_output:
            return self._dicts(keys, vals, all_orders=True)
        return self._convert(self._tensor(keys, vals, A.degree + 1), torch_output, tf_output)

    def num_one_forms_bracket(self, bivector: Dict, one_form_1: Dict, one_form_2: Dict, mesh,
                              torch_output: bool = False, tf_output: bool = False,
                              dict_output: bool = False):
        """``{alpha, beta}_P`` on every point, shape ``(N, n, 1)``; empty array if both forms
        lie in the kernel of ``P`` (as NumericalPoissonGeometry)."""
        mesh = self._mesh(mesh)
        if self.pg.is_in_kernel(bivector, one_form_1) and self.pg.is_in_kernel(bivector, one_form_2):
            return self._empty(torch_output, tf_output, dict_output)
        return self._vector(
            "one_forms_bracket", (bivector, one_form_1, one_form_2),
            lambda: calc.one_forms_bracket(self.pg._P(bivector).matrix,
                                           self._reader.one_form(one_form_1, "one_form_1"),
                                           self._reader.one_form(one_form_2, "one_form_2"),
                                           self.coords),
            mesh, torch_output, tf_output, dict_output)

    # ------------------------------------------------------------------ constructions
    def num_linear_normal_form_R3(self, linear_bivector: Dict, mesh, torch_output: bool = False,
                                  tf_output: bool = False, dict_output: bool = False):
        """The linear normal form (:meth:`PoissonGeometry.linear_normal_form_R3`) on every point.

        Raises
        ------
        InputError
            For the non-unimodular families, whose normal form keeps a free parameter ``a``.
        """
        if self.dim != 3:
            raise DimensionError(f"the dimension {self.dim} != 3")
        form = self.pg.linear_normal_form_R3(linear_bivector)
        return self.num_bivector(form, mesh, torch_output, tf_output, dict_output)

    def num_gauge_transformation(self, bivector: Dict, two_form: Dict, mesh,
                                 torch_output: bool = False, tf_output: bool = False,
                                 dict_output: bool = False):
        """``P (I - B P)^{-1}`` on every point, shape ``(N, n, n)``.

        Raises
        ------
        InputError
            If ``I - B P`` is singular at a mesh point (NumericalPoissonGeometry silently drops
            such points, which misaligns its output with the mesh).
        """
        mesh = self._mesh(mesh)
        P = self.num_bivector(bivector, mesh)
        B = self.num_bivector(two_form, mesh)
        M = np.eye(self.dim) - B @ P
        det = np.linalg.det(M)
        singular = np.abs(det) <= 1e-12 * np.maximum(1.0, np.abs(M).max(axis=(1, 2)) ** self.dim)
        if singular.any():
            k = int(np.argmax(singular))
            raise InputError(f"I - B P is singular at {int(singular.sum())} mesh point(s), first at "
                             f"row {k}: {mesh[k].tolist()}")
        # P M^{-1} = (M^{-T} P^T)^T, solved for all points at once
        G = np.swapaxes(np.linalg.solve(np.swapaxes(M, 1, 2), np.swapaxes(P, 1, 2)), 1, 2)
        G = 0.5 * (G - np.swapaxes(G, 1, 2))  # exactly antisymmetric (it is, up to round-off)
        if dict_output:
            iu = np.triu_indices(self.dim, 1)
            keys = list(zip(*iu))
            return self._dicts(keys, G[:, iu[0], iu[1]].T)
        return self._convert(G, torch_output, tf_output)

    def num_flaschka_ratiu_bivector(self, casimirs: Sequence[object], mesh,
                                    symplectic_form: bool = False, torch_output: bool = False,
                                    tf_output: bool = False, dict_output: bool = False):
        """Flaschka–Ratiu bivector (and optionally its 2-form) on every point, ``(N, n, n)``."""
        mesh = self._mesh(mesh)
        if self.dim < 3:
            raise DimensionError(f"the dimension {self.dim} < 3")
        if isinstance(casimirs, (str, bytes)) or len(casimirs) != self.dim - 2:
            raise CasimirError(f"need a list of {self.dim - 2} Casimir functions")

        def derive_fr():
            K = [self._reader.expr(c, "casimir") for c in casimirs]
            return calc.flaschka_ratiu(K, self.coords)

        def derive_form():
            FR = derive_fr()
            norm = sum(v ** 2 for v in FR.values())
            return {k: -v / norm for k, v in FR.items()}

        keys, vals = self._matrices("flaschka_ratiu", (list(casimirs),), derive_fr, mesh)
        outs = [(keys, vals)]
        if symplectic_form:
            outs.append(self._matrices("flaschka_ratiu_form", (list(casimirs),), derive_form, mesh))
        if dict_output:
            res = [self._dicts(k, v) for k, v in outs]
        else:
            res = [self._convert(self._tensor(k, v, 2), torch_output, tf_output) for k, v in outs]
        return tuple(res) if symplectic_form else res[0]


#: The name used in the task and in NumericalPoissonGeometry's paper.
NumericalPoissonGeometry = NumPoissonGeometry

__all__ = ["NumPoissonGeometry", "NumericalPoissonGeometry"]
