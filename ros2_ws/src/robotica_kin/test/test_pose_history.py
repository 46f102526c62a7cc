"""PoseHistory: the nearest kept pose within a tolerance, the oldest dropped, bad poses refused."""
import math

import pytest
from robotica_kin.mobile.pose_history import PoseHistory


def test_nearest_within_tolerance():
    history = PoseHistory(size=10)
    for k in range(5):
        history.add(0.02 * k, (float(k), 0.0, 0.0))
    assert history.nearest(0.041, 0.005).tolist() == [2.0, 0.0, 0.0]
    assert history.nearest(0.05, 0.009) is None          # 0.01 s from either neighbour
    assert history.nearest(0.05, 0.01)[0] in (2.0, 3.0)


def test_the_oldest_pose_is_dropped():
    history = PoseHistory(size=2)
    for k in range(3):
        history.add(float(k), (float(k), 0.0, 0.0))
    assert len(history) == 2 and history.nearest(0.0, 0.5) is None
    assert PoseHistory().nearest(0.0, 1.0) is None       # empty


@pytest.mark.parametrize('stamp, pose', [(math.nan, (0, 0, 0)), (0.0, (0, math.inf, 0)),
                                         (0.0, (0, 0))])
def test_bad_poses_are_refused(stamp, pose):
    with pytest.raises(ValueError, match='finite'):
        PoseHistory().add(stamp, pose)
    with pytest.raises(ValueError, match='size'):
        PoseHistory(size=0)
