"""
Stick drawing and animation of a serial manipulator (HEMERO ``plotbot``, catalog §12.2).

``plotbot(dh, q, opt)`` draws the arm as a stick figure through the origins of the link frames
{0} … {n} (Craig's modified DH, book §4.3) and the tool frame, with matplotlib: one drawing for
one configuration, an animation for a joint trajectory (one configuration per row), as the
HEMERO toolbox does in Ej. H.3.1 ([H] fig. 3.2, the planar 3R along an arc of radius 5 m).

Matplotlib is imported inside :func:`plotbot` only, so importing this module does not load it
(the functional core stays free of plotting, STYLE.md §2).
"""

import math
import os
from pathlib import Path
from typing import Any, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robotica_kin.dh import as_dh_model, DHModel
from robotica_kin.forward_kinematics import fkine, link_frames

if TYPE_CHECKING:  # pragma: no cover - for the annotations only
    from matplotlib.animation import FuncAnimation
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ['PLOTBOT_OPTIONS', 'plotbot']

#: The option characters of ``opt`` and their meaning (HEMERO's, catalog §12.2).
PLOTBOT_OPTIONS = {
    'd': '2-D drawing in the XY plane',
    'f': 'draw every link frame {0} ... {n}',
    'w': 'draw the end-effector (tool) frame',
    'l': 'do not erase between animation steps (draw every configuration)',
    'r': 'repeat the animation (loop while shown)',
}

_SAVE_SUFFIXES = ('.png', '.gif', '.mp4')
_AXIS_COLORS = ('r', 'g', 'b')        # x, y, z axes of a frame, as tf frames in RViz
_FRAME_SCALE_OF_REACH = 0.15          # default frame-axis length / reach of the motion
_LINK_WIDTH = 4.0                     # [pt]
_JOINT_FRAME_WIDTH = 1.2              # [pt]
_TOOL_FRAME_WIDTH = 2.5               # [pt]
GID_LINK = 'plotbot:link'
GID_FRAME = 'plotbot:frame'
GID_TOOL = 'plotbot:tool'


def _parse_opt(opt: str) -> frozenset[str]:
    if not isinstance(opt, str):
        raise ValueError(f'opt must be a string of option characters, got {opt!r}')
    unknown = sorted(set(opt) - set(PLOTBOT_OPTIONS))
    if unknown:
        valid = ', '.join(f"'{c}' ({text})" for c, text in PLOTBOT_OPTIONS.items())
        raise ValueError(f'unknown plotbot option(s) {unknown} in opt={opt!r}; valid: {valid}')
    return frozenset(opt)


def _positive(name: str, value: Any, what: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0.0):
        raise ValueError(f'{name} must be a finite {what} > 0, got {value!r}')
    return number


def _save_suffix(save: str | os.PathLike[str] | None) -> str | None:
    if save is None:
        return None
    suffix = Path(save).suffix.lower()
    if suffix not in _SAVE_SUFFIXES:
        raise ValueError(f'save must end in one of {_SAVE_SUFFIXES}, got {str(save)!r}')
    return suffix


class _Pose:
    """The matplotlib lines of one drawn configuration: the stick and the frame axes."""

    def __init__(self, ax: 'Axes', planar: bool, link_color: Any, n_frames: int,
                 with_tool: bool) -> None:
        self.planar = planar
        self.stick = self._line(ax, color=link_color, linewidth=_LINK_WIDTH, marker='o',
                                markersize=7.0, markerfacecolor='w', markeredgecolor='k',
                                zorder=2.0, gid=GID_LINK)
        self.frames = [[self._line(ax, color=c, linewidth=_JOINT_FRAME_WIDTH, zorder=3.0,
                                   gid=GID_FRAME) for c in _AXIS_COLORS]
                       for _ in range(n_frames)]
        self.tool = [self._line(ax, color=c, linewidth=_TOOL_FRAME_WIDTH, zorder=2.5,
                                gid=GID_TOOL) for c in _AXIS_COLORS] if with_tool else []

    def _line(self, ax: 'Axes', **style: Any) -> Any:
        empty: list[float] = []
        if self.planar:
            (line,) = ax.plot(empty, empty, **style)
        else:
            (line,) = ax.plot(empty, empty, empty, **style)
        return line

    def _set(self, line: Any, points: NDArray[np.float64]) -> None:
        if self.planar:
            line.set_data(points[:, 0], points[:, 1])
        else:
            line.set_data_3d(points[:, 0], points[:, 1], points[:, 2])

    def _set_frame(self, lines: list[Any], T: NDArray[np.float64], scale: float) -> None:
        origin = T[:3, 3]
        for k, line in enumerate(lines):
            self._set(line, np.stack([origin, origin + scale * T[:3, k]]))

    def set_pose(self, vertices: NDArray[np.float64], frames: NDArray[np.float64],
                 tool: NDArray[np.float64], scale: float) -> None:
        self._set(self.stick, vertices)
        for lines, T in zip(self.frames, frames):
            self._set_frame(lines, T, scale)
        if self.tool:
            self._set_frame(self.tool, tool, scale)

    @property
    def artists(self) -> list[Any]:
        return [self.stick, *(line for lines in self.frames for line in lines), *self.tool]

    def set_visible(self, visible: bool) -> None:
        for artist in self.artists:
            artist.set_visible(visible)


def _set_limits(ax: 'Axes', points: NDArray[np.float64], margin: float, planar: bool) -> None:
    """Fix equal-aspect axis limits around every drawn point, with ``margin`` [m] around."""
    lo = points.min(axis=0) - margin
    hi = points.max(axis=0) + margin
    if planar:
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect('equal', adjustable='box')
        return
    centre = 0.5 * (lo + hi)
    half = 0.5 * float(np.max(hi - lo))
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)  # type: ignore[attr-defined]
    ax.set_box_aspect((1.0, 1.0, 1.0))  # type: ignore[arg-type]


def plotbot(dh: DHModel | ArrayLike, q: ArrayLike, opt: str = '', *, ax: 'Axes | None' = None,
            save: str | os.PathLike[str] | None = None, fps: float = 10.0,
            link_color: Any = 'c', frame_scale: float | None = None
            ) -> 'Figure | FuncAnimation':
    """
    Draw or animate a manipulator as a stick figure (HEMERO ``plotbot``, catalog §12.2).

    The stick joins the origins of the link frames {0} … {n} (``link_frames``) and of the
    tool frame (``fkine``; it coincides with {n} when the model has no tool): links are thick
    lines in ``link_color`` (cyan, as HEMERO), joints are round markers. Frames are drawn as
    three lines of length ``frame_scale`` along their x (red), y (green) and z (blue) axes, as
    tf frames are shown in RViz; HEMERO's own colours (joint frames red, end-effector frame
    green) are not used because they hide which axis is which. The tool frame is drawn
    with thicker lines than the link frames. Every line carries a gid: ``'plotbot:link'``
    (one per configuration, vertices {0} … {n} then the tool), ``'plotbot:frame'`` (x, y, z
    of {0}, then of {1}, …) and ``'plotbot:tool'``; the stick always has n + 2 vertices.
    [H] fig. 3.2 is ``plotbot(dh, q, 'dfwl')`` on the Ej. H.3.1 arc.

    The axis limits are fixed once from every frame origin of every configuration (plus
    ``frame_scale``), with equal scales on all axes, so an animation does not rescale.

    Parameters
    ----------
    dh : DHModel or array_like, shape (n, 4) or (n, 5)
        The robot (a raw HEMERO table ``[alpha a theta d sigma]`` is accepted).
    q : array_like, shape (n,) or (m, n)
        Joint values [rad or m]: one configuration, or a trajectory of m (one per row).
    opt : str
        HEMERO's option characters, in any order (see :data:`PLOTBOT_OPTIONS`):
        ``d`` 2-D drawing of the projection on the XY plane of {0} (an ordinary Axes with
        equal aspect; without ``d`` a 3-D Axes with ``set_box_aspect((1, 1, 1))``);
        ``f`` draw every link frame {0} … {n}; ``w`` draw the tool frame; ``l`` do not erase
        between steps: draw all m configurations in one figure; ``r`` repeat the animation
        while it is shown (matplotlib loops until the window closes; HEMERO repeats 50 times).
    ax : matplotlib Axes, optional
        Draw into this Axes (3-D, or 2-D with ``d``); default a new pyplot figure.
    save : str or path-like, optional
        Also write the drawing to this file: ``.png`` (a drawing only: one configuration or
        ``l``), ``.gif`` (Pillow; it always loops) or ``.mp4`` (ffmpeg), at ``fps``; the
        directory must exist. With ``l`` a video adds one configuration per frame, as HEMERO
        animates without erasing; a single configuration gives a one-frame video.
    fps : float
        Animation rate [frames/s] when shown or saved as a video; > 0.
    link_color : matplotlib colour
        Colour of the links; default ``'c'`` (cyan).
    frame_scale : float, optional
        Length of the drawn frame axes [m or the table's length unit]; default 0.15 times
        the largest distance of a frame origin from the base over the whole motion.

    Returns
    -------
    matplotlib.figure.Figure or matplotlib.animation.FuncAnimation
        The Figure for one configuration (shape (n,) or (1, n)) or with ``l``; for m > 1
        configurations without ``l`` the ``FuncAnimation`` with m frames (keep a reference
        to it while it is shown, as matplotlib requires; pass ``ax`` to hold its Figure).
        Nothing is shown here, with or without ``save``: call ``matplotlib.pyplot.show()``
        to see the figure, and close it (``pyplot.close(fig)``) when done.

    Raises
    ------
    ValueError
        For a bad table, a q of the wrong size, with NaN or empty, an unknown ``opt``
        character, a ``save`` suffix other than .png/.gif/.mp4, .png for an animation,
        ``fps`` or ``frame_scale`` not > 0, an unknown colour, or an ``ax`` whose kind
        (2-D/3-D) does not match ``opt``.
    RuntimeError
        When ``save`` ends in .mp4 and ffmpeg is not installed.

    Examples
    --------
    Ej. H.3.1's planar 3R (l1 = 4 m, l2 = 3 m) with every frame, in the XY plane:

    >>> import matplotlib
    >>> matplotlib.use('Agg')  # no window
    >>> import matplotlib.pyplot as plt
    >>> from robotica_kin.robots import planar_rrr
    >>> fig = plotbot(planar_rrr(4.0, 3.0), [0.0, np.pi / 2, 0.0], 'dfw')
    >>> stick = [line for line in fig.axes[0].lines if line.get_gid() == 'plotbot:link'][0]
    >>> stick.get_xydata()[-1].round(6).tolist()    # (4.10): l1 c1 + l2 c12, l1 s1 + l2 s12
    [4.0, 3.0]
    >>> plt.close(fig)

    """
    robot = as_dh_model(dh)
    qq = np.atleast_2d(robot.check_q(q))
    m = qq.shape[0]
    if m == 0:
        raise ValueError(f'q must hold at least one configuration, got shape {qq.shape}')
    flags = _parse_opt(opt)
    suffix = _save_suffix(save)
    save_path = None if save is None else Path(save)
    planar = 'd' in flags
    animated = m > 1 and 'l' not in flags
    if animated and suffix == '.png':
        raise ValueError(f'cannot save an animation of {m} configurations as .png: save it as '
                         '.gif or .mp4, add the option l to draw them all in one picture, or '
                         'pass one configuration')
    fps = _positive('fps', fps, 'number [frames/s]')
    if frame_scale is not None:
        frame_scale = _positive('frame_scale', frame_scale, 'length')

    import matplotlib.animation as mpl_animation
    import matplotlib.colors as mpl_colors
    if not mpl_colors.is_color_like(link_color):
        raise ValueError(f'link_color must be a matplotlib colour, got {link_color!r}')
    if suffix == '.mp4' and not mpl_animation.FFMpegWriter.isAvailable():
        raise RuntimeError(f'saving {str(save)!r} needs ffmpeg, which was not found: install '
                           'ffmpeg (e.g. apt-get install ffmpeg) or save as .gif')
    if ax is not None and (getattr(ax, 'name', '') == '3d') == planar:
        want = '2-D Axes (option d)' if planar else "3-D Axes (projection='3d'; or option d)"
        raise ValueError(f'opt={opt!r} draws into a {want}, got a {ax.name!r} Axes')

    frames = link_frames(robot, qq)                        # (m, n + 1, 4, 4): T_0_i
    tools = fkine(robot, qq).reshape(m, 4, 4)              # T_0_tool
    vertices = np.concatenate([frames[:, :, :3, 3], tools[:, np.newaxis, :3, 3]], axis=1)
    if frame_scale is None:
        reach = float(np.max(np.linalg.norm(vertices, axis=-1)))
        frame_scale = _FRAME_SCALE_OF_REACH * reach if reach > 0.0 else 1.0
    scale = float(frame_scale)
    margin = 1.1 * scale if flags & {'f', 'w'} else 0.1 * scale
    drawn = vertices.reshape(-1, 3)[:, :2] if planar else vertices.reshape(-1, 3)

    import matplotlib.pyplot as plt
    if ax is None:
        fig = plt.figure()
        ax = fig.add_subplot(projection=None if planar else '3d')
        ax.set_xlabel('x [m]')
        ax.set_ylabel('y [m]')
        if not planar:
            ax.set_zlabel('z [m]')  # type: ignore[attr-defined]
        ax.set_title(robot.name)
    else:
        fig = ax.get_figure(root=True)  # type: ignore[assignment]
    n_frames = robot.n + 1 if 'f' in flags else 0
    poses = [_Pose(ax, planar, link_color, n_frames, 'w' in flags)
             for _ in range(1 if animated else m)]
    for k, pose in enumerate(poses):
        pose.set_pose(vertices[k], frames[k], tools[k], scale)
    _set_limits(ax, drawn, margin, planar)

    def show_step(k: int) -> list[Any]:
        if animated:
            poses[0].set_pose(vertices[k], frames[k], tools[k], scale)
            return poses[0].artists
        for j, pose in enumerate(poses):    # option l: configurations 0 … k
            pose.set_visible(j <= k)
        return [artist for pose in poses for artist in pose.artists]

    if animated:
        anim = mpl_animation.FuncAnimation(
            fig, show_step, frames=m, interval=1000.0 / fps, repeat='r' in flags,
            cache_frame_data=False)
        if save_path is not None:
            anim.save(save_path, writer=_writer(mpl_animation, suffix, fps))
        return anim
    if save_path is None:
        return fig
    if suffix == '.png':
        fig.savefig(save_path)
    else:   # a drawing as a video: one configuration more per frame
        writer = _writer(mpl_animation, suffix, fps)
        with writer.saving(fig, save_path, dpi=None):
            for k in range(m):
                show_step(k)
                writer.grab_frame()
    return fig


def _writer(mpl_animation: Any, suffix: str | None, fps: float) -> Any:
    if suffix == '.gif':
        return mpl_animation.PillowWriter(fps=fps)
    return mpl_animation.FFMpegWriter(fps=fps)
