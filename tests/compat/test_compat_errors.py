"""Bad input to the PoissonGeometry front end raises typed errors (never eval, never NaN)."""

from __future__ import annotations

import numpy as np
import pytest

from poissonkit.compat import (
    CasimirError,
    DiferentialFormError,
    FunctionError,
    MultivectorError,
    Nonhomogeneous,
    Nonlinear,
    NumPoissonGeometry,
    PoissonGeometry,
)
from poissonkit.errors import DimensionError, InputError, ParseError, PoissonkitError

SO3 = {(1, 2): "x3", (1, 3): "-x2", (2, 3): "x1"}
INJECTIONS = [
    "__import__('os').system('echo pwned')",
    "x1.__class__",
    "(lambda: 1)()",
    "x1[0]",
    "open('f')",
    "eval('1')",
    "'abc'",
]


@pytest.mark.parametrize("text", INJECTIONS)
def test_code_injection_in_functions_is_rejected(text, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    pg = PoissonGeometry(3)
    with pytest.raises(ParseError):
        pg.hamiltonian_vf(SO3, text)
    with pytest.raises(ParseError):
        pg.poisson_bracket(SO3, "x1", text)
    with pytest.raises(ParseError):
        pg.is_casimir(SO3, text)
    assert not (tmp_path / "f").exists()


@pytest.mark.parametrize("text", INJECTIONS[:3])
def test_code_injection_in_dict_values_is_rejected(text):
    pg = PoissonGeometry(3)
    with pytest.raises(ParseError):
        pg.bivector_to_matrix({(1, 2): text})
    with pytest.raises(ParseError):
        pg.sharp_morphism(SO3, {(1,): text})
    with pytest.raises(ParseError):
        pg.coboundary_operator(SO3, {(1, 2, 3): text})
    with pytest.raises(ParseError):
        pg.flaschka_ratiu_bivector([text])
    with pytest.raises(ParseError):
        NumPoissonGeometry(3).num_hamiltonian_vf(SO3, text, np.zeros((2, 3)))


def test_out_of_range_coordinate_names_are_rejected():
    with pytest.raises(ParseError, match="x7"):
        PoissonGeometry(3).hamiltonian_vf(SO3, "x7**2")
    with pytest.raises(ParseError, match="x0"):
        PoissonGeometry(3).bivector_to_matrix({(1, 2): "x0"})
    # other names are free parameters, as in PoissonGeometry's documented examples
    assert PoissonGeometry(3).poisson_bracket(SO3, "a*x1", "x2") == "a*x3"


def test_syntax_errors_are_parse_errors():
    with pytest.raises(ParseError):
        PoissonGeometry(3).hamiltonian_vf(SO3, "x1 +* x2")
    with pytest.raises(ParseError):
        PoissonGeometry(3).hamiltonian_vf(SO3, "")


@pytest.mark.parametrize("bivector, error", [
    ({(1, 1): "x1"}, MultivectorError),            # repeated index
    ({(0, 2): "x1"}, MultivectorError),            # indices are 1-based
    ({(-1, 2): "x1"}, MultivectorError),
    ({(1, 4): "x1"}, DimensionError),              # out of range in dimension 3
    ({(1, 2): "x3", (2, 1): "x3"}, MultivectorError),  # the same entry twice
    ({(1, 2, 3): "x1"}, MultivectorError),         # not a bivector
    ({(1, 2): "x1", (1,): "x2"}, MultivectorError),  # keys of different lengths
    ({"12": "x1"}, MultivectorError),              # not an index tuple
    ({(1.5, 2): "x1"}, MultivectorError),
    ({(1.0, 2): "x1"}, MultivectorError),          # floats are not indices
    ({(True, 2): "x1"}, MultivectorError),
    ([("x1",)], DimensionError),                   # not a dict, not an n x n matrix
    ("x1", MultivectorError),                      # not a dict
])
def test_malformed_bivectors_raise_typed_errors(bivector, error):
    with pytest.raises(error):
        PoissonGeometry(3).bivector_to_matrix(bivector)


def test_errors_are_poissonkit_input_errors():
    for cls in (MultivectorError, DiferentialFormError, FunctionError, CasimirError, Nonlinear,
                Nonhomogeneous):
        assert issubclass(cls, InputError) and issubclass(cls, PoissonkitError)
        assert issubclass(cls, ValueError)


def test_a_bivector_object_of_the_wrong_size_is_rejected():
    from poissonkit.structure import so3

    with pytest.raises(DimensionError):
        PoissonGeometry(4).bivector_to_matrix(so3())
    # the right size is accepted, renamed to x1..x3
    assert PoissonGeometry(3).is_poisson_bivector(so3())


def test_matrix_input_must_be_antisymmetric_and_of_the_right_size():
    pg = PoissonGeometry(3)
    with pytest.raises(InputError, match="antisymmetric"):
        pg.bivector_to_matrix([[0, "x3", 0], ["x3", 0, 0], [0, 0, 0]])
    with pytest.raises(InputError, match="antisymmetric"):
        pg.is_poisson_bivector(np.array([[1.0, 0, 0], [0, 0, 0], [0, 0, 0]]))
    with pytest.raises(DimensionError):
        pg.bivector_to_matrix([[0, 1], [-1, 0]])
    with pytest.raises(ParseError):
        pg.bivector_to_matrix([[0, "__import__('os')", 0], [0, 0, 0], [0, 0, 0]])
    # a correct matrix is the same bivector as its dict
    M = [[0, "x3", "-x2"], ["-x3", 0, "x1"], ["x2", "-x1", 0]]
    assert pg.bivector_to_matrix(M) == pg.bivector_to_matrix(SO3)


@pytest.mark.parametrize("dimension", [1, 0, -3, 2.0, "3", True])
def test_bad_dimensions(dimension):
    with pytest.raises(DimensionError):
        PoissonGeometry(dimension)
    with pytest.raises(DimensionError):
        NumPoissonGeometry(dimension)


def test_one_form_errors():
    pg = PoissonGeometry(3)
    with pytest.raises(DiferentialFormError):
        pg.sharp_morphism(SO3, {(0,): "x1"})
    with pytest.raises(DiferentialFormError):
        pg.sharp_morphism(SO3, {(1, 2): "x1"})
    with pytest.raises(DimensionError):
        pg.is_in_kernel(SO3, {(4,): "x1"})


def test_operation_specific_errors():
    pg = PoissonGeometry(3)
    with pytest.raises(FunctionError):
        pg.curl_operator(SO3, "0")
    with pytest.raises(FunctionError):
        pg.modular_vf(SO3, "x1 - x1")
    with pytest.raises(MultivectorError):
        pg.curl_operator({}, "1")
    with pytest.raises(CasimirError):
        PoissonGeometry(4).flaschka_ratiu_bivector(["x1"])
    with pytest.raises(DimensionError):
        PoissonGeometry(2).flaschka_ratiu_bivector([])
    with pytest.raises(Nonlinear):
        pg.linear_normal_form_R3({(1, 2): "x1*x2"})
    with pytest.raises(Nonlinear):
        pg.linear_normal_form_R3({(1, 2): "x1 + 1"})
    with pytest.raises(DimensionError):
        PoissonGeometry(4).linear_normal_form_R3({(1, 2): "x1"})
    with pytest.raises(Nonhomogeneous):
        pg.is_unimodular_homogeneous({(1, 2): "x1 + x2**2"})
    with pytest.raises(Nonhomogeneous):
        pg.is_unimodular_homogeneous({(1, 2): "1/x1"})


def test_mesh_errors():
    npg = NumPoissonGeometry(3)
    with pytest.raises(DimensionError):
        npg.num_hamiltonian_vf(SO3, "x1", np.zeros((4, 2)))
    with pytest.raises(DimensionError):
        npg.num_hamiltonian_vf(SO3, "x1", np.zeros(3))
    with pytest.raises(InputError):
        npg.num_hamiltonian_vf(SO3, "x1", [[1, 2, "a"]])
    with pytest.raises(InputError, match="free parameters"):
        npg.num_hamiltonian_vf(SO3, "a*x1", np.zeros((2, 3)))
    # a result that is not finite at a mesh point is an error naming the point, not a NaN
    with pytest.raises(InputError, match="row 1"):
        npg.num_hamiltonian_vf(SO3, "1/(x1 - x2)", np.array([[1.0, 2.0, 3.0], [1.0, 1.0, 0.0]]))
    # I - B P singular at a point: an error (NumericalPoissonGeometry silently drops the point)
    with pytest.raises(InputError, match="singular"):
        NumPoissonGeometry(2).num_gauge_transformation({(1, 2): "1"}, {(1, 2): "-1"},
                                                       np.ones((3, 2)))
    with pytest.raises(ImportError):
        # neither PyTorch nor TensorFlow is a dependency; asking for them names the install
        try:
            import torch  # noqa: F401
            pytest.skip("PyTorch is installed")
        except ImportError:
            npg.num_bivector(SO3, np.zeros((1, 3)), torch_output=True)


def test_read_bivector_accepts_json_style_keys_and_rejects_bad_ones():
    from poissonkit.compat import read_bivector

    P = read_bivector({"1,2": "x3", "(1, 3)": "-x2", "[2, 3]": "x1"})
    assert P.dim == 3 and PoissonGeometry(3).bivector_to_matrix(P) == \
        PoissonGeometry(3).bivector_to_matrix(SO3)
    assert read_bivector({(1, 2): "x3"}, dim=4).dim == 4
    with pytest.raises(MultivectorError):
        read_bivector({"1;2": "x3"})
    with pytest.raises(MultivectorError):
        read_bivector({"__import__('os')": "x3"})
    with pytest.raises(ParseError):
        read_bivector({"1,2": "__import__('os').getcwd()"})
    with pytest.raises(DimensionError):
        read_bivector({"1,4": "x1"}, dim=3)
