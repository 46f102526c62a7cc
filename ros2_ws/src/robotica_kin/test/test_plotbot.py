"""
Tests of robotica_kin.plotbot: HEMERO's stick drawing and animation (catalog 12.2, 12.6).

Reference values are the planar 3R's closed-form forward kinematics (4.10) of Ej. 4.1,
written out here (l1 c1, l1 c1 + l2 c12, ...), its closed-form inverse on the arc of Ej. H.3.1
(radius 5 m with l1 = 4 m, l2 = 3 m: a 3-4-5 triangle, so q2 = pi/2 exactly), and the
PUMA 560's spherical wrist (fig. A.1: the last three frames share their origin).
"""

import gc
import math

import matplotlib
from matplotlib import animation
import matplotlib.pyplot as plt
import numpy as np
from PIL import Image
import pytest
from robotica_kin.plotbot import plotbot, PLOTBOT_OPTIONS
from robotica_kin.robots import planar_rrr, puma560

matplotlib.use('Agg')  # no window; before any figure is made

L1, L2 = 4.0, 3.0  # Ej. H.3.1 [m]
ARC_RADIUS = 5.0   # [m]
ARC_X = np.linspace(0.0, ARC_RADIUS, 5)  # five poses, as fig. 3.2


@pytest.fixture(autouse=True)
def small_figures():
    """Draw at a low resolution and close every figure after each test."""
    with matplotlib.rc_context({'figure.dpi': 30, 'savefig.dpi': 30,
                                'figure.figsize': (4.0, 3.0)}):
        yield
    plt.close('all')


def planar_origins(q, l1=L1, l2=L2, l3=0.0):
    """Return the origins of {0}, {1}, {2}, {3} and the tool of Ej. 4.1, from (4.10)."""
    q1, q2, q3 = q
    c1, s1 = math.cos(q1), math.sin(q1)
    c12, s12 = math.cos(q1 + q2), math.sin(q1 + q2)
    c123, s123 = math.cos(q1 + q2 + q3), math.sin(q1 + q2 + q3)
    p2 = (l1 * c1, l1 * s1)
    p3 = (p2[0] + l2 * c12, p2[1] + l2 * s12)
    tool = (p3[0] + l3 * c123, p3[1] + l3 * s123)
    return np.array([(0.0, 0.0), (0.0, 0.0), p2, p3, tool])


def arc_configurations():
    """Return q (5, 3) along the arc of Ej. H.3.1 (phi = 0), by closed-form inverse kinematics."""
    y = np.sqrt(ARC_RADIUS ** 2 - ARC_X ** 2)
    q2 = math.acos((ARC_RADIUS ** 2 - L1 ** 2 - L2 ** 2) / (2.0 * L1 * L2))  # = pi/2
    q1 = np.arctan2(y, ARC_X) - math.atan2(L2 * math.sin(q2), L1 + L2 * math.cos(q2))
    return np.column_stack([q1, np.full_like(q1, q2), -q1 - q2]), np.column_stack([ARC_X, y])


def lines_by_gid(ax, gid):
    return [line for line in ax.lines if line.get_gid() == gid]


def vertices(line):
    """Return the (k, 3) vertices of a 3-D line or the (k, 2) vertices of a 2-D one."""
    if hasattr(line, 'get_data_3d'):
        return np.column_stack(line.get_data_3d())
    return np.asarray(line.get_xydata())


@pytest.mark.parametrize('q', [[0.3, 0.9, -0.5], [0.0, math.pi / 2, 0.0], [-2.0, 1.0, 3.0]])
@pytest.mark.parametrize('l3', [0.0, 2.0])
def test_stick_through_frame_origins_2d(q, l3):
    fig = plotbot(planar_rrr(L1, L2, l3), q, 'd')
    (stick,) = lines_by_gid(fig.axes[0], 'plotbot:link')
    np.testing.assert_allclose(vertices(stick), planar_origins(q, l3=l3), atol=1e-12)


def test_stick_through_frame_origins_3d():
    q = [0.3, 0.9, -0.5]
    fig = plotbot(planar_rrr(L1, L2), q)
    (stick,) = lines_by_gid(fig.axes[0], 'plotbot:link')
    expected = np.column_stack([planar_origins(q), np.zeros(5)])
    np.testing.assert_allclose(vertices(stick), expected, atol=1e-12)


def test_raw_hemero_table_is_accepted():
    table = [[0, 0, 0, 0, 0], [0, L1, 0, 0, 0], [0, L2, 0, 0, 0]]
    fig = plotbot(table, [0.0, math.pi / 2, 0.0], 'd')
    (stick,) = lines_by_gid(fig.axes[0], 'plotbot:link')
    np.testing.assert_allclose(vertices(stick)[-1], [L1, L2], atol=1e-12)


def test_puma_spherical_wrist_frames_share_an_origin():
    # Appendix fig. A.1: the frames {4}, {5}, {6} of the PUMA 560 have the same origin.
    fig = plotbot(puma560(), [0.2, -0.4, 0.3, 0.5, -0.7, 0.9], 'fw')
    (stick,) = lines_by_gid(fig.axes[0], 'plotbot:link')
    wrist = vertices(stick)[4:]
    assert wrist.shape == (4, 3)  # {4}, {5}, {6}, tool (identity tool)
    np.testing.assert_allclose(wrist - wrist[0], 0.0, atol=1e-12)
    assert np.linalg.norm(wrist[0]) > 0.3  # the wrist is away from the base


def test_d_gives_2d_axes_and_default_3d_with_equal_scales():
    q = [0.3, 0.9, -0.5]
    ax2 = plotbot(planar_rrr(L1, L2), q, 'd').axes[0]
    assert ax2.name == 'rectilinear'
    assert ax2.get_aspect() == 1.0
    ax3 = plotbot(planar_rrr(L1, L2), q).axes[0]
    assert ax3.name == '3d'
    np.testing.assert_allclose(ax3.get_box_aspect() / ax3.get_box_aspect()[0], 1.0)
    spans = [np.ptp(lim) for lim in (ax3.get_xlim(), ax3.get_ylim(), ax3.get_zlim())]
    np.testing.assert_allclose(spans, spans[0])


@pytest.mark.parametrize('opt, n_frame_lines, n_tool_lines', [
    ('', 0, 0), ('f', 3 * 4, 0), ('w', 0, 3), ('fw', 3 * 4, 3), ('dfw', 3 * 4, 3)])
def test_frame_options_add_three_lines_per_frame(opt, n_frame_lines, n_tool_lines):
    ax = plotbot(planar_rrr(L1, L2), [0.3, 0.9, -0.5], opt).axes[0]
    assert len(lines_by_gid(ax, 'plotbot:link')) == 1
    assert len(lines_by_gid(ax, 'plotbot:frame')) == n_frame_lines  # {0} ... {3}
    assert len(lines_by_gid(ax, 'plotbot:tool')) == n_tool_lines


def test_frame_axes_point_along_the_frame():
    # Frame {i} of the planar 3R is turned by q1 + ... + qi about z (Ej. 4.1).
    q = [0.3, 0.9, -0.5]
    scale = 0.5
    ax = plotbot(planar_rrr(L1, L2, 2.0), q, 'dfw', frame_scale=scale).axes[0]
    frame_lines = lines_by_gid(ax, 'plotbot:frame')
    origins = planar_origins(q, l3=2.0)
    headings = np.concatenate([[0.0], np.cumsum(q)])
    for i, heading in enumerate(headings):
        x_axis, y_axis, z_axis = frame_lines[3 * i:3 * i + 3]
        c, s = math.cos(heading), math.sin(heading)
        np.testing.assert_allclose(vertices(x_axis), [origins[i], origins[i] + scale * np.array(
            [c, s])], atol=1e-12)
        np.testing.assert_allclose(vertices(y_axis), [origins[i], origins[i] + scale * np.array(
            [-s, c])], atol=1e-12)
        np.testing.assert_allclose(vertices(z_axis), [origins[i], origins[i]], atol=1e-12)
        assert [line.get_color() for line in (x_axis, y_axis, z_axis)] == ['r', 'g', 'b']
    tool_x = lines_by_gid(ax, 'plotbot:tool')[0]
    np.testing.assert_allclose(vertices(tool_x)[0], origins[4], atol=1e-12)


def test_ejemplo_h_3_1_arc_with_l_draws_every_pose():
    # Catalog 12.6, Ej. H.3.1 (b), fig. 3.2: five poses of the 3R along the arc of radius 5 m.
    q, tips = arc_configurations()
    fig = plotbot(planar_rrr(L1, L2), q, 'dfwl')
    ax = fig.axes[0]
    sticks = lines_by_gid(ax, 'plotbot:link')
    assert len(sticks) == len(q)
    assert len(lines_by_gid(ax, 'plotbot:frame')) == len(q) * 3 * 4
    assert len(lines_by_gid(ax, 'plotbot:tool')) == len(q) * 3
    for stick, qk, tip in zip(sticks, q, tips):
        np.testing.assert_allclose(vertices(stick), planar_origins(qk), atol=1e-12)
        np.testing.assert_allclose(vertices(stick)[-1], tip, atol=1e-12)
        assert math.hypot(*vertices(stick)[-1]) == pytest.approx(ARC_RADIUS, abs=1e-12)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    assert x0 <= 0.0 and x1 >= ARC_RADIUS and y0 <= 0.0 and y1 >= ARC_RADIUS


def test_ejemplo_h_3_1_arc_without_l_is_an_animation_of_m_frames(tmp_path):
    q, tips = arc_configurations()
    anim = plotbot(planar_rrr(L1, L2), q, 'dfw', save=tmp_path / 'arc.gif')
    assert isinstance(anim, animation.FuncAnimation)
    ax = anim._fig.axes[0]
    assert len(lines_by_gid(ax, 'plotbot:link')) == 1  # erased and redrawn
    limits = (ax.get_xlim(), ax.get_ylim())
    with Image.open(tmp_path / 'arc.gif') as gif:
        assert gif.n_frames == len(q)
    (stick,) = lines_by_gid(ax, 'plotbot:link')
    np.testing.assert_allclose(vertices(stick)[-1], tips[-1], atol=1e-12)  # last pose shown
    assert (ax.get_xlim(), ax.get_ylim()) == limits  # the animation does not rescale
    for x0, x1 in limits:
        assert x0 <= 0.0 and x1 >= ARC_RADIUS


def test_l_saved_as_gif_adds_one_pose_per_frame(tmp_path):
    q, _ = arc_configurations()
    fig = plotbot(planar_rrr(L1, L2), q, 'dl', save=tmp_path / 'arc.gif')
    with Image.open(tmp_path / 'arc.gif') as gif:
        assert gif.n_frames == len(q)
    assert all(line.get_visible() for line in fig.axes[0].lines)


@pytest.mark.filterwarnings('ignore:Animation was deleted without rendering')
@pytest.mark.parametrize('opt, repeat', [('d', False), ('dr', True)])
def test_r_repeats_the_animation(opt, repeat):
    q, _ = arc_configurations()
    anim = plotbot(planar_rrr(L1, L2), q, opt, fps=20.0)
    assert anim._repeat is repeat
    assert anim._interval == pytest.approx(50.0)  # [ms] at 20 frames/s
    del anim
    gc.collect()  # never shown: matplotlib's deletion warning is filtered here, not later


@pytest.mark.parametrize('name, q, opt', [
    ('pose.png', [0.3, 0.9, -0.5], 'dfw'), ('pose.gif', [0.3, 0.9, -0.5], 'fw'),
    ('arc.png', 'arc', 'dl')])
def test_save_png_and_gif(tmp_path, name, q, opt):
    if q == 'arc':
        q, _ = arc_configurations()
    path = tmp_path / name
    plotbot(planar_rrr(L1, L2), q, opt, save=path)
    assert path.stat().st_size > 0
    with Image.open(path) as image:
        assert image.format == path.suffix[1:].upper()
        assert image.size[0] > 50 and image.size[1] > 50


def test_save_mp4_needs_ffmpeg(tmp_path, monkeypatch):
    monkeypatch.setattr(animation.FFMpegWriter, 'isAvailable', classmethod(lambda cls: False))
    q, _ = arc_configurations()
    with pytest.raises(RuntimeError, match='install ffmpeg.*gif'):
        plotbot(planar_rrr(L1, L2), q, 'd', save=tmp_path / 'arc.mp4')
    assert not (tmp_path / 'arc.mp4').exists()


def test_never_shows(monkeypatch, tmp_path):
    def refuse(*args, **kwargs):
        raise AssertionError('plotbot must not call plt.show()')
    monkeypatch.setattr(plt, 'show', refuse)
    plotbot(planar_rrr(L1, L2), [0.3, 0.9, -0.5])
    plotbot(planar_rrr(L1, L2), [0.3, 0.9, -0.5], save=tmp_path / 'pose.png')


def test_draws_into_a_given_axes():
    fig = plt.figure()
    ax = fig.add_subplot()
    assert plotbot(planar_rrr(L1, L2), [0.3, 0.9, -0.5], 'd', ax=ax, link_color='m') is fig
    assert plt.get_fignums() == [fig.number]
    (stick,) = lines_by_gid(ax, 'plotbot:link')
    assert stick.get_color() == 'm'


@pytest.mark.parametrize('q, opt, kwargs, match', [
    ([0.3, 0.9, -0.5], 'dx', {}, 'valid:.*d.*f.*w.*l.*r'),
    ([0.3, 0.9, -0.5], 'd', {'save': 'pose.jpg'}, r'\.png'),
    ([0.3, 0.9], 'd', {}, 'shape'),
    ([[0.3, 0.9, -0.5, 0.0]], 'd', {}, 'shape'),
    ([0.3, math.nan, -0.5], 'd', {}, 'finite'),
    (np.zeros((0, 3)), 'd', {}, 'at least one'),
    ('arc', 'd', {'save': 'arc.png'}, r'\.gif'),
    ([0.3, 0.9, -0.5], 'd', {'fps': 0.0}, 'fps'),
    ([0.3, 0.9, -0.5], 'd', {'frame_scale': -1.0}, 'frame_scale'),
    ([0.3, 0.9, -0.5], 'd', {'frame_scale': math.inf}, 'frame_scale'),
    ([0.3, 0.9, -0.5], 'd', {'link_color': 'not a colour'}, 'colour'),
])
def test_bad_input_raises_value_error(tmp_path, q, opt, kwargs, match):
    if isinstance(q, str):
        q, _ = arc_configurations()
    if 'save' in kwargs:
        kwargs = {**kwargs, 'save': tmp_path / kwargs['save']}
    with pytest.raises(ValueError, match=match):
        plotbot(planar_rrr(L1, L2), q, opt, **kwargs)
    assert plt.get_fignums() == []  # no figure left behind
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize('opt, projection', [('d', '3d'), ('', None)])
def test_axes_of_the_wrong_kind_is_refused(opt, projection):
    ax = plt.figure().add_subplot(projection=projection)
    with pytest.raises(ValueError, match='Axes'):
        plotbot(planar_rrr(L1, L2), [0.3, 0.9, -0.5], opt, ax=ax)
    assert len(ax.lines) == 0


def test_options_are_hemero_s():
    assert sorted(PLOTBOT_OPTIONS) == sorted('dfwlr')
