"""
HEMERO's function names in one namespace, so a MATLAB script ports line by line.

``from robotica_kin.hemero import *`` is deliberately not supported (no star imports); write
``from robotica_kin import hemero as h`` and call ``h.fkine(dh, q)``, or import the names you
use. The implementations live in topical modules, where each function documents its book
equation:

=====================  ============================================================
HEMERO (book, [H])     robotica_kin module
=====================  ============================================================
transl rotx roty rotz  :mod:`robotica_kin.transforms` (ch. 3, §A.2)
rotvec trinv ishomog
rpy2tr tr2rpy eul2tr
tr2eul (+ tr2q q2tr
tr2angvec angvec2tr)
linktrans              :mod:`robotica_kin.dh` (4.5)
fkine                  :mod:`robotica_kin.forward_kinematics` (4.6)
ikine                  :mod:`robotica_kin.ik` (§4.4, [H] ikine; ``ikine_solve``, ``IKError``)
jacob0 jacobn          :mod:`robotica_kin.jacobian` ([H] (3.13)-(3.22))
velprop                :mod:`robotica_kin.velocity_propagation` (4.52)-(4.58)
tr2diff diff2tr        :mod:`robotica_kin.differential_motion` ([H] (3.1)-(3.27))
tr2jac
plotbot                :mod:`robotica_kin.plotbot`
rne inertia gravity    :mod:`robotica_kin.dynamics` (ch. 5, §A.3; Pinocchio RNEA, CRBA, ABA)
coriolis friction fdyn
dhp560 (+ dyn)         :func:`robotica_kin.robots.puma560`
=====================  ============================================================

Differences from MATLAB: NumPy arrays, rows are configurations (q of shape (m, n)), a
"trajectory of transforms" is an (m, 4, 4) array, ``ikine`` takes its optional arguments by
keyword (the book's examples and its manual disagree on their order, catalog §17), and
``ikine`` raises :class:`IKError` where HEMERO stopped with an error.
"""

from robotica_kin.dh import linktrans
from robotica_kin.differential_motion import diff2tr, tr2diff, tr2jac
from robotica_kin.dynamics import coriolis, fdyn, friction, gravity, inertia, rne
from robotica_kin.forward_kinematics import fkine
from robotica_kin.ik import IKError, ikine, ikine_solve, IKResult
from robotica_kin.jacobian import jacob0, jacobn
from robotica_kin.plotbot import plotbot
from robotica_kin.robots import puma560
from robotica_kin.transforms import (angvec2tr, eul2tr, ishomog, q2tr, rotvec, rotx, roty, rotz,
                                     rpy2tr, tr2angvec, tr2eul, tr2q, tr2rpy, transl, trinv)
from robotica_kin.velocity_propagation import velprop

__all__ = [
    'IKError', 'IKResult', 'angvec2tr', 'coriolis', 'diff2tr', 'eul2tr', 'fdyn', 'fkine',
    'friction', 'gravity', 'ikine', 'ikine_solve', 'inertia', 'ishomog', 'jacob0', 'jacobn',
    'linktrans', 'plotbot', 'puma560', 'q2tr', 'rne', 'rotvec', 'rotx', 'roty', 'rotz', 'rpy2tr',
    'tr2angvec', 'tr2diff', 'tr2eul', 'tr2jac', 'tr2q', 'tr2rpy', 'transl', 'trinv', 'velprop',
]
