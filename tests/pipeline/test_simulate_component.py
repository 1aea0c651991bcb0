"""pipeline.response.simulate_component: one component of a record file, checked, simulated."""

from __future__ import annotations

from pathlib import Path

import pytest
from obspy import Stream

from stepframe.errors import InputError
from stepframe.pipeline.dynamics.response import simulate_component, simulate_record
from stepframe.records import read
from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

RECORD = "peer_nga_west2/RSN8883_14383980_13849360.AT2"


def test_the_component_is_simulated_as_simulate_record_does(data_dir: Path) -> None:
    import tomllib

    frame = frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))
    stream = read(data_dir / RECORD)
    simulated = simulate_component(frame, stream, name="rec.AT2", scale=6.0, tail_s=5.0)
    direct = simulate_record(frame, stream[0], scale=6.0, tail_s=5.0, name="rec.AT2")
    assert simulated.to_dict() == direct.to_dict()
    assert simulated.describe() == direct.describe()
    two = Stream([stream[0], stream[0].copy()])
    with pytest.raises(InputError, match=r"rec\.AT2: 2 components"):
        simulate_component(frame, two, name="rec.AT2")
    # One rule with the command's options (--scale in (0, 10⁴], --tail-s in [0, 3600]): a
    # second one here refused the documented --tail-s 0 and accepted less scale.
    with pytest.raises(InputError, match=r"--scale 20000, expected in \(0, 10000\]"):
        simulate_component(frame, stream, name="rec.AT2", scale=2e4)
    with pytest.raises(InputError, match=r"--tail-s 3601, expected in \[0, 3600\]"):
        simulate_component(frame, stream, name="rec.AT2", tail_s=3601.0)
    no_tail = simulate_component(frame, stream, name="rec.AT2", scale=2e3, tail_s=0.0)
    assert (
        no_tail.to_dict()
        == simulate_record(frame, stream[0], scale=2e3, tail_s=0.0, name="rec.AT2").to_dict()
    )
    assert no_tail.to_dict()["tail_s"] == 0.0
