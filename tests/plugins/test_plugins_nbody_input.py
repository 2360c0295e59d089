"""The bundled n-body plugin rejects a non-graph with a typed error, not an AttributeError."""

from __future__ import annotations

import networkx as nx
import poissonkit_nbody
import pytest

from poissonkit.errors import InputError


@pytest.mark.parametrize("not_a_graph", ["abc", None, [("a", "b")], {"a": {}}])
def test_from_graph_of_a_non_graph_is_an_input_error(not_a_graph):
    with pytest.raises(InputError, match="networkx graph"):
        poissonkit_nbody.from_graph(not_a_graph)


def test_initial_state_of_a_non_graph_is_an_input_error():
    with pytest.raises(InputError, match="networkx graph"):
        poissonkit_nbody.initial_state("abc", None)


def test_empty_graph_is_still_reported_as_having_no_bodies():
    with pytest.raises(InputError, match="no bodies"):
        poissonkit_nbody.from_graph(nx.Graph())
