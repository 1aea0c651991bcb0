"""Shared inputs of the selection tests: the Example 4 frame, a stiffer test frame, and the
features of the embedded example catalogue (computed once per session)."""

from __future__ import annotations

import tomllib
from typing import Any

import pytest

from stepframe.structure.frame import PortalFrame
from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping


@pytest.fixture(scope="session")
def example4() -> PortalFrame:
    """The paper's Example 4 frame (the frame template)."""
    return frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))


@pytest.fixture(scope="session")
def example_inputs() -> tuple[Any, Any, Any]:
    """Features of the 100 FEMA P695 components joined with metadata, samples, failures."""
    from stepframe.pipeline.selection.inputs import example_catalogue

    return example_catalogue(jobs=1)
