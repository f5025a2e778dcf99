"""Formation offsets: leader 0.5 m ahead of the first row, rows centred, first robot leftmost."""

from __future__ import annotations

import pytest

from dancebots.plan.formation import formation_offsets
from dancebots.scenario import Formation, parse_scenario


def first_formation(text: str) -> Formation:
    scenario, diagnostics = parse_scenario(text)
    assert scenario is not None, diagnostics
    formation = scenario.instructions[0]
    assert isinstance(formation, Formation)
    return formation


def test_square_of_listing_6_3() -> None:
    offsets = formation_offsets(first_formation("robots R1 R2 R3 R4\nsquare R1,R2;R3,R4 1.2 1;1\n"))
    assert offsets == {
        "R1": pytest.approx((-0.5, 0.5)),
        "R2": pytest.approx((-0.5, -0.5)),
        "R3": pytest.approx((-1.7, 0.5)),
        "R4": pytest.approx((-1.7, -0.5)),
    }


def test_row_of_listing_7_1() -> None:
    offsets = formation_offsets(first_formation("robots R1 R2\nrow R1,R2 0 1.2\n"))
    assert offsets == {"R1": pytest.approx((-0.5, 0.6)), "R2": pytest.approx((-0.5, -0.6))}


def test_triangle_with_per_gap_values() -> None:
    text = "robots A B C D E F\ntriangle A;B,C;D,E,F 1.5,2 0;1.2;1,1.4\n"
    offsets = formation_offsets(first_formation(text))
    assert offsets["A"] == pytest.approx((-0.5, 0.0))
    assert offsets["B"] == pytest.approx((-2.0, 0.6))
    assert offsets["C"] == pytest.approx((-2.0, -0.6))
    # third row: gaps 1 and 1.4, width 2.4, centred: 1.2, 0.2, -1.2
    assert offsets["D"] == pytest.approx((-4.0, 1.2))
    assert offsets["E"] == pytest.approx((-4.0, 0.2))
    assert offsets["F"] == pytest.approx((-4.0, -1.2))


def test_column_and_custom_lead() -> None:
    offsets = formation_offsets(first_formation("robots R1 R3\ncolumn R1;R3 1.2 0\n"), lead=1.0)
    assert offsets == {"R1": pytest.approx((-1.0, 0.0)), "R3": pytest.approx((-2.2, 0.0))}
