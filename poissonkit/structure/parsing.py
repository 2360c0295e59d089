"""Safe parsing of user expressions: an allow-list of names, never ``eval``/bare ``sympify``.

Strings are tokenised by sympy's parser with ``global_dict`` restricted to a fixed table of
functions and constants, and ``local_dict`` restricted to the caller's symbols. Any other name,
attribute access, subscript, lambda or dunder is rejected before parsing.

Names (the rule of :mod:`poissonkit.conventions`, "Text expressions"): a name the caller
declares — a coordinate, a parameter, an ``extra`` name — always means that symbol, even
``I``, ``E``, ``S``, ``N``, ``pi``, a Unicode identifier (``α``) or a Python keyword
(``lambda``). Undeclared, ``pi`` is π and nothing else is a constant: ``I`` and ``E`` are
refused (an undeclared moment of inertia ``I`` must not silently become √−1), as are ``S``
and ``N``. Numbers: in exact mode (the default) a decimal such as ``0.1`` is the rational
1/10, so that symbolic checks stay exact; ``exact=False`` keeps sympy floats.
"""

from __future__ import annotations

import ast
import io
import keyword
import math
import re
import tokenize
import unicodedata
from fractions import Fraction
from collections.abc import Iterable, Mapping
from typing import Union

import sympy as sp
from sympy.parsing.sympy_parser import parse_expr, standard_transformations

from poissonkit.conventions import EXACT_DECIMALS, UNDECLARED_NAMES
from poissonkit.errors import InputError, ParseError
# the public home of the non-string conversion: parse text here, convert values with as_expr
from poissonkit.structure._expr import as_expr

__all__ = ["ALLOWED_FUNCTIONS", "ASSUMPTIONS", "MAX_DIGITS", "MAX_EXPONENT", "MAX_LENGTH",
           "ParameterSpec", "as_expr", "declare_parameters", "parse_expression"]

ALLOWED_FUNCTIONS: dict[str, object] = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "asin": sp.asin, "acos": sp.acos,
    "atan": sp.atan, "atan2": sp.atan2, "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh,
    "exp": sp.exp, "log": sp.log, "sqrt": sp.sqrt, "Abs": sp.Abs, "abs": sp.Abs,
    "pi": sp.pi, "Rational": sp.Rational, "Integer": sp.Integer,
    "Float": sp.Float, "Symbol": sp.Symbol,
}
#: Names sympy's own parser reads as constants or functions: here they mean only what the
#: caller declares (undeclared: refused, with this hint).
UNDECLARED_HINTS: dict[str, str] = {
    "I": "the imaginary unit is not read from text (an undeclared I would be sqrt(-1))",
    "E": "Euler's number is exp(1) (an undeclared E would be it)",
    "S": "sympy's S is not available", "N": "sympy's N is not available",
}
assert set(UNDECLARED_HINTS) == set(UNDECLARED_NAMES)  # one rule (poissonkit.conventions)
#: Names a parameter may not take: the parser's functions (``pi`` may be declared).
_FUNCTIONS = frozenset(ALLOWED_FUNCTIONS) - {"pi"}
_ALLOWED_NODES = (
    ast.Expression, ast.BinOp, ast.UnaryOp, ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow,
    ast.USub, ast.UAdd, ast.Constant, ast.Name, ast.Load, ast.Call, ast.Mod,
)

#: Longest accepted expression text (longer input is refused before any parsing work).
MAX_LENGTH = 10_000
#: Largest absolute value of a constant exponent (``x**1000`` is fine, ``9**9**9`` is not).
MAX_EXPONENT = 1000
#: Largest number of decimal digits a constant sub-expression may reach (``(10**1000)**1000``).
MAX_DIGITS = 10_000

_ARITH = {ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b,
          ast.Mult: lambda a, b: a * b, ast.Div: lambda a, b: a / b}


#: Calls that turn a constant into a constant (``Integer(10**999)**1000`` is as large as
#: ``(10**999)**1000``): the size checks look through them.
_NUMERIC_CALLS = ("Integer", "Rational", "Float", "Abs", "abs")


def _numeric_call_args(node: ast.AST) -> list[ast.AST] | None:
    """The arguments of a call of a numeric constructor (``None`` for anything else)."""
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id in _NUMERIC_CALLS and node.args and not node.keywords):
        return list(node.args)
    return None


def _exponent_value(node: ast.AST, text: str) -> float | None:
    """Value of a constant exponent (float arithmetic, no powers), or ``None`` if not constant.

    Only evaluated to bound its size: the expression itself is built by sympy from the text.
    """
    args = _numeric_call_args(node)
    if args is not None:
        vals = [_exponent_value(a, text) for a in args]
        if any(v is None for v in vals):
            return None
        if len(vals) == 2:  # Rational(p, q): only its size matters
            return math.inf if vals[1] == 0 else vals[0] / vals[1]
        return abs(vals[0]) if node.func.id in ("Abs", "abs") else vals[0]
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        try:
            return float(node.value)
        except OverflowError:
            return math.inf
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        v = _exponent_value(node.operand, text)
        return None if v is None else -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp):
        if isinstance(node.op, ast.Pow):
            a, b = _exponent_value(node.left, text), _exponent_value(node.right, text)
            if a is not None and b is not None:
                raise ParseError(f"a constant power as an exponent (tower of powers) is not "
                                 f"allowed in {text[:80]!r}")
            return None
        a, b = _exponent_value(node.left, text), _exponent_value(node.right, text)
        if a is None or b is None or type(node.op) not in _ARITH:
            return None
        try:
            return _ARITH[type(node.op)](a, b)
        except (OverflowError, ZeroDivisionError):
            return math.inf
    return None


def _digits(node: ast.AST) -> float | None:
    """Upper bound of the decimal digits of a constant sub-expression, ``None`` if not constant."""
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        v = abs(node.value)
        return float(len(str(v))) if isinstance(v, int) else max(0.0, math.log10(v + 1.0))
    if isinstance(node, ast.UnaryOp):
        return _digits(node.operand)
    args = _numeric_call_args(node)
    if args is not None:
        sizes = [_digits(a) for a in args]
        return None if any(d is None for d in sizes) else sum(sizes) + 1.0
    if isinstance(node, ast.BinOp):
        a, b = _digits(node.left), _digits(node.right)
        if a is None or b is None:
            return None
        if isinstance(node.op, ast.Pow):
            e = _exponent_value(node.right, "")
            return math.inf if e is None else (abs(e) + 1.0) * (a + 1.0)
        return a + b + 1.0
    return None


def _check_powers(tree: ast.AST, text: str) -> None:
    """Refuse powers that would make sympy compute astronomically large numbers."""
    for node in ast.walk(tree):
        if not (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow)):
            continue
        e = _exponent_value(node.right, text)
        if e is not None and not abs(e) <= MAX_EXPONENT:
            raise ParseError(f"constant exponent {e:g} exceeds {MAX_EXPONENT} in absolute value "
                             f"in {text[:80]!r}")
        d = _digits(node)
        if d is not None and d > MAX_DIGITS:
            raise ParseError(f"a constant in {text[:80]!r} would have more than {MAX_DIGITS} digits")


#: Assumptions a declared parameter may carry (``{"m": {"positive": True}}``).
ASSUMPTIONS = ("real", "positive", "negative", "nonnegative", "nonpositive", "nonzero",
               "integer", "rational")

#: How parameters are declared: names, symbols, or ``{name: assumptions | symbol}``.
ParameterSpec = Union[Iterable[Union[str, sp.Symbol]],
                      Mapping[str, Union[Mapping[str, bool], sp.Symbol, None]], None]


def _parameter_symbol(name: object, how: object) -> sp.Symbol:
    """One declared parameter: ``how`` is ``None``, an assumptions mapping or a symbol."""
    if isinstance(name, sp.Symbol) and how is None:
        return name
    if not isinstance(name, str) or not name.isidentifier() or name.startswith("_"):
        raise InputError(f"parameter name {name!r} is not an identifier (letters, digits, _, "
                         "not starting with _ or a digit)")
    if unicodedata.normalize("NFKC", name) != name:  # Python reads the text NFKC-normalised
        raise InputError(f"parameter name {name!r}: write it as "
                         f"{unicodedata.normalize('NFKC', name)!r} (its normal form)")
    if name in _FUNCTIONS:
        raise InputError(f"parameter name {name!r} is a function or constant of the parser")
    if isinstance(how, sp.Symbol):
        if how.name != name:
            raise InputError(f"parameter {name!r} is declared as the symbol {how.name!r}")
        return how
    assumptions = {} if how is None else how
    if not isinstance(assumptions, Mapping):
        raise InputError(f"parameter {name!r}: expected an assumptions mapping such as "
                         f"{{'positive': True}} or a sympy Symbol, got {type(how).__name__}")
    for key, value in assumptions.items():
        if key not in ASSUMPTIONS or not isinstance(value, bool):
            raise InputError(f"parameter {name!r}: assumption {key!r}={value!r} is not one of "
                             f"{', '.join(ASSUMPTIONS)} with a True/False value")
    # real by default, like the coordinates: a parameter then cancels against its conjugate
    return sp.Symbol(name, **{"real": True, **assumptions})


def declare_parameters(params: ParameterSpec,
                       reserved: Iterable[sp.Symbol | str] = ()) -> dict[str, sp.Symbol]:
    """The symbols of declared parameters, by name.

    Parameters
    ----------
    params
        ``None``; a sequence of names or sympy symbols (``["a", "b"]``); or a mapping
        ``{name: assumptions}`` with assumptions among :data:`ASSUMPTIONS`
        (``{"m": {"positive": True}}``) or ``{name: symbol}``. A name becomes a *real*
        symbol (as coordinates are) plus the stated assumptions; a symbol is used as given.
    reserved
        Names already taken (the coordinates): a parameter may not reuse one.

    Returns
    -------
    dict
        ``{name: Symbol}``, in declaration order.

    Raises
    ------
    InputError
        A name that is not an identifier, a parser function name (``sin``, ``exp``), a
        coordinate's name, repeated, or an unknown assumption.

    Examples
    --------
    >>> declare_parameters({"a": {"positive": True}, "b": None})["a"].is_positive
    True
    """
    if params is None:
        return {}
    if isinstance(params, (str, bytes, sp.Basic)):
        raise InputError(f"params must be a sequence of names or a mapping name -> "
                         f"assumptions, got {params!r:.60}")
    pairs = params.items() if isinstance(params, Mapping) else ((p, None) for p in params)
    taken = {str(r) for r in reserved}
    out: dict[str, sp.Symbol] = {}
    for name, how in pairs:
        sym = _parameter_symbol(name, how)
        if sym.name in taken:
            raise InputError(f"parameter {sym.name!r} has the name of a coordinate")
        if sym.name in out:
            raise InputError(f"parameter {sym.name!r} is declared twice")
        out[sym.name] = sym
    return out


def parse_expression(text: str, symbols: Iterable[sp.Symbol] = (),
                     extra: Mapping[str, object] | None = None, *,
                     params: ParameterSpec = None, exact: bool = EXACT_DECIMALS) -> sp.Expr:
    """Parse ``text`` into a sympy expression using only allowed names.

    Parameters
    ----------
    text
        The expression, e.g. ``"x1*x2 - sin(x3)"``. ``^`` is read as a power.
    symbols
        Symbols that may appear (matched by name).
    extra
        More allowed names (parameter symbols, user functions), by name.
    params
        Parameters the text may name, declared as in :func:`declare_parameters`
        (``["a", "b"]`` or ``{"m": {"positive": True}}``).
    exact
        Read decimals as the rationals they denote (``0.1`` is 1/10; default), or as sympy
        floats (``False``).

    Raises
    ------
    ParseError
        On a syntax error or any name, attribute, subscript or construct not allowed; on text
        longer than :data:`MAX_LENGTH`; on a constant exponent above :data:`MAX_EXPONENT` in
        absolute value, a tower of constant powers (``9**9**9``) or a constant with more than
        :data:`MAX_DIGITS` digits (these would make sympy compute for hours); on an expression
        that evaluates to a non-finite value (``1/0``, ``0/0``, ``log(0)``).
    """
    if not isinstance(text, str):
        raise ParseError(f"expected a string expression, got {type(text).__name__}")
    if len(text) > MAX_LENGTH:
        raise ParseError(f"expression is {len(text)} characters long; at most {MAX_LENGTH} "
                         "are accepted")
    src = text.replace("^", "**").strip()
    if not src:
        raise ParseError("empty expression")
    if isinstance(symbols, sp.Symbol):  # a single symbol is a common slip: accept it
        symbols = (symbols,)
    local = {str(s): s for s in symbols}
    if extra:
        local.update(extra)
    if params is not None:
        local.update(declare_parameters(params, reserved=[str(s) for s in symbols]))
    src, local = _rename_keywords(src, local)
    try:
        tree = ast.parse(src, mode="eval")
    except SyntaxError as exc:
        words = [w for w in re.findall(r"\w+", src) if keyword.iskeyword(w)]
        hint = (f" ({words[0]!r} is a Python keyword: declare it as a parameter to use it as a "
                "name)") if words else ""
        raise ParseError(f"cannot parse {text!r}: {exc.msg}{hint}") from None
    except (RecursionError, MemoryError):
        raise ParseError("expression is nested too deeply") from None
    for node in ast.walk(tree):
        if not isinstance(node, _ALLOWED_NODES):
            raise ParseError(f"construct {type(node).__name__} is not allowed in {text!r}")
        if isinstance(node, ast.Name):
            if node.id in UNDECLARED_HINTS and node.id not in local:
                raise ParseError(f"name {node.id!r} is not declared in {text!r}: declare it as "
                                 f"a parameter to use it as a symbol; {UNDECLARED_HINTS[node.id]}")
            if node.id.startswith("_") or (node.id not in local and node.id not in ALLOWED_FUNCTIONS):
                raise ParseError(f"name {node.id!r} is not allowed in {text!r}; allowed: "
                                 f"{', '.join(local) or '(none)'} (coordinates and declared "
                                 "parameters; declare more with params=[...]); functions "
                                 f"and constants: {', '.join(sorted(ALLOWED_FUNCTIONS))}")
        if isinstance(node, ast.Call) and not isinstance(node.func, ast.Name):
            raise ParseError(f"only calls of named functions are allowed in {text!r}")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise ParseError(f"constant {node.value!r} is not allowed in {text!r}")
    try:
        _check_powers(tree, text)
    except RecursionError:
        raise ParseError("expression is nested too deeply") from None
    if exact:
        src = _exact_decimals(src, text)
    try:
        expr = parse_expr(src, local_dict=dict(local), global_dict=dict(ALLOWED_FUNCTIONS),
                          transformations=standard_transformations, evaluate=True)
    except Exception as exc:  # sympy raises many types; report them uniformly
        raise ParseError(f"cannot parse {text!r}: {exc}") from None
    # "1/0", "0/0", "log(0)" evaluate to zoo / nan: refuse them here rather than let a
    # non-finite value reach a bracket or a Hamiltonian
    if not isinstance(expr, sp.Expr):  # "cos" alone is a function class; "True" a boolean
        raise ParseError(f"{text!r} is not an expression (got {type(expr).__name__})")
    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
        raise ParseError(f"{text!r} is not finite (evaluates to {expr})")
    return expr


def _rename_keywords(src: str, local: dict[str, object]) -> tuple[str, dict[str, object]]:
    """Declared names that are Python keywords (``lambda``) renamed in ``src`` to identifiers
    the grammar accepts (``lambda_``, made unique), mapped to the same symbols."""
    words = [w for w in local if keyword.iskeyword(w) and re.search(rf"(?<!\w){w}(?!\w)", src)]
    if not words:
        return src, local
    local = dict(local)
    for word in words:
        alias = word + "_"
        while alias in local or alias in src:
            alias += "_"
        src = re.sub(rf"(?<![\w.]){word}(?!\w)", alias, src)
        local[alias] = local[word]
    return src, local


_DECIMAL = re.compile(r"(?:\d[\d_]*)?\.?\d*(?:[eE][+-]?\d+)?")


def _exact_decimals(src: str, text: str) -> str:
    """``src`` with every decimal literal (``0.1``, ``2.5e-3``) replaced by the exact
    ``Rational(p, q)`` it denotes; integers are exact already."""
    out = []
    try:
        tokens = list(tokenize.generate_tokens(io.StringIO(src).readline))
    except (tokenize.TokenError, SyntaxError):  # already parsed by ast: cannot happen
        return src
    for tok in tokens:
        value = tok.string
        if tok.type == tokenize.NUMBER and any(c in value for c in ".eE") \
                and not value.lower().startswith(("0x", "0o", "0b")) and _DECIMAL.fullmatch(value):
            exponent = re.search(r"[eE]([+-]?\d+)", value)
            if exponent and abs(int(exponent.group(1))) > MAX_DIGITS:
                raise ParseError(f"the number {value} in {text[:80]!r} has more than "
                                 f"{MAX_DIGITS} digits")
            q = Fraction(value.replace("_", ""))
            value = f"Rational({q.numerator}, {q.denominator})"
        out.append((tok.type, value))
    return tokenize.untokenize(out)
