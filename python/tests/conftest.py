"""Shared fixtures of the Python tests: the real clips in ../shared/data (MOTIONMAP_SHARED_DATA,
never copied into the repository; a test skips, saying so, when its file is absent) and the
`motionmap` tool of the same build (MOTIONMAP_CLI), which the module's results are compared
with. ctest sets both (python/CMakeLists.txt)."""
import os

import pytest

DATA = os.environ.get("MOTIONMAP_SHARED_DATA",
                      os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))

GOLF = "cmu/64_08.bvh"            # 365 frames, CMU skeleton
GOLF2 = "cmu/64_09.bvh"           # 453 frames, the same skeleton
OTHER = "other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh"  # another skeleton
AMC = "asfamc/02_02.amc"          # with asfamc/02.asf beside it


def data_path(rel):
    path = os.path.join(DATA, rel)
    if not os.path.exists(path):
        pytest.skip(f"{rel} absent from the shared data ({DATA})")
    return path


@pytest.fixture
def golf():
    return data_path(GOLF)


@pytest.fixture
def golf2():
    return data_path(GOLF2)


@pytest.fixture
def other():
    return data_path(OTHER)


@pytest.fixture
def amc():
    return data_path(AMC)


@pytest.fixture
def cli():
    path = os.environ.get("MOTIONMAP_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("MOTIONMAP_CLI (the motionmap tool of this build) not set")
    return path
