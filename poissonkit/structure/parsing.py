"""Safe parsing of user expressions: an allow-list of names, never ``eval``/bare ``sympify``.

Strings are tokenised by sympy's parser with ``global_dict`` restricted to a fixed table of
functions and constants, and ``local_dict`` restricted to the caller's symbols. Any other name,
attribute access, subscript, lambda or dunder is rejected before parsing.
"""

from __future__ import annotations

import ast
from collections.abc import Iterable, Mapping

import sympy as sp
from sympy.parsing.sympy_parser import parse_expr, standard_transformations

from poissonkit.errors import ParseError

ALLOWED_FUNCTIONS: dict[str, object] = {
    "sin": sp.sin, "cos": sp.cos, "tan": sp.tan, "asin": sp.asin, "acos": sp.acos,
    "atan": sp.atan, "atan2": sp.atan2, "sinh": sp.sinh, "cosh": sp.cosh, "tanh": sp.tanh,
    "exp": sp.exp, "log": sp.log, "sqrt": sp.sqrt, "Abs": sp.Abs, "abs": sp.Abs,
    "pi": sp.pi, "E": sp.E, "I": sp.I, "Rational": sp.Rational, "Integer": sp.Integer,
    "Float": sp.Float, "Symbol": sp.Symbol,
}
_ALLOWED_NODES = (
    ast.Expression, ast.BinOp, ast.UnaryOp, ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow,
    ast.USub, ast.UAdd, ast.Constant, ast.Name, ast.Load, ast.Call, ast.Mod,
)


def parse_expression(text: str, symbols: Iterable[sp.Symbol] = (),
                     extra: Mapping[str, object] | None = None) -> sp.Expr:
    """Parse ``text`` into a sympy expression using only allowed names.

    Parameters
    ----------
    text
        The expression, e.g. ``"x1*x2 - sin(x3)"``. ``^`` is read as a power.
    symbols
        Symbols that may appear (matched by name).
    extra
        More allowed names (parameters, user functions).

    Raises
    ------
    ParseError
        On a syntax error or any name, attribute, subscript or construct not allowed.
    """
    if not isinstance(text, str):
        raise ParseError(f"expected a string expression, got {type(text).__name__}")
    src = text.replace("^", "**").strip()
    if not src:
        raise ParseError("empty expression")
    local = {str(s): s for s in symbols}
    if extra:
        local.update(extra)
    try:
        tree = ast.parse(src, mode="eval")
    except SyntaxError as exc:
        raise ParseError(f"cannot parse {text!r}: {exc.msg}") from None
    for node in ast.walk(tree):
        if not isinstance(node, _ALLOWED_NODES):
            raise ParseError(f"construct {type(node).__name__} is not allowed in {text!r}")
        if isinstance(node, ast.Name):
            if node.id.startswith("_") or (node.id not in local and node.id not in ALLOWED_FUNCTIONS):
                allowed = sorted(set(local) | set(ALLOWED_FUNCTIONS))
                raise ParseError(f"name {node.id!r} is not allowed in {text!r}; allowed: "
                                 + ", ".join(allowed))
        if isinstance(node, ast.Call) and not isinstance(node.func, ast.Name):
            raise ParseError(f"only calls of named functions are allowed in {text!r}")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise ParseError(f"constant {node.value!r} is not allowed in {text!r}")
    try:
        return parse_expr(src, local_dict=dict(local), global_dict=dict(ALLOWED_FUNCTIONS),
                          transformations=standard_transformations, evaluate=True)
    except Exception as exc:  # sympy raises many types; report them uniformly
        raise ParseError(f"cannot parse {text!r}: {exc}") from None
