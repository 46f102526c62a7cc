"""
robotica's compiled inner loops (package ``robotica_native``), loaded with ctypes on first use.

One shared library on Pinocchio's C++ API with a plain C interface: ``rik_*`` is the search of
:mod:`robotica_kin.ik` (ik_search.cpp), ``ras_*`` the RK4 step of
:mod:`robotica_sim.simulation.arm` with its joint stops (arm_step.cpp). The callers validate
every input; the functions here only load the library and describe its signatures.
"""

import ctypes
import functools
import os
from typing import Any

from numpy.typing import NDArray

__all__ = ['ERROR_SIZE', 'address', 'native_library']

ERROR_SIZE = 512   # bytes of the C interface's error message buffers


@functools.lru_cache(maxsize=1)
def native_library() -> ctypes.CDLL:
    """
    Return the loaded library, its functions' signatures declared.

    Raises
    ------
    RuntimeError
        When the package is not built or its environment not sourced.

    """
    # Imported here: the core modules import without a ROS environment.
    from ament_index_python.packages import get_package_prefix, PackageNotFoundError
    try:
        prefix = get_package_prefix('robotica_native')
    except (PackageNotFoundError, OSError) as error:   # OSError: AMENT_PREFIX_PATH not set
        raise RuntimeError('the compiled package robotica_native is missing: run '
                           'scripts/setup.sh, then source scripts/env.sh') from error
    lib = ctypes.CDLL(os.path.join(prefix, 'lib', 'librobotica_native.so'))
    pointer, long, double, text = ctypes.c_void_p, ctypes.c_long, ctypes.c_double, ctypes.c_char_p
    lib.rik_robot_new.restype = pointer
    lib.rik_robot_new.argtypes = [text, text, pointer, long, pointer, pointer, double, text, long]
    lib.rik_robot_free.restype = None
    lib.rik_robot_free.argtypes = [pointer]
    lib.rik_solve.restype = long
    lib.rik_solve.argtypes = [pointer, long, pointer, pointer, pointer, double, long, long,
                              ctypes.c_uint64, pointer, text, long]
    lib.ras_arm_new.restype = pointer
    lib.ras_arm_new.argtypes = [text, pointer, pointer, pointer, pointer, pointer, pointer,
                                text, long]
    lib.ras_arm_free.restype = None
    lib.ras_arm_free.argtypes = [pointer]
    lib.ras_arm_step.restype = long
    lib.ras_arm_step.argtypes = [pointer, pointer, pointer, pointer, double, text, long]
    return lib


def address(array: NDArray[Any]) -> int:
    """Return the address of a C-contiguous array's data (for the C interface)."""
    return int(array.__array_interface__['data'][0])
