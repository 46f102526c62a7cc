"""
Message definitions for bags: a rosbags type store that also knows this workspace's types.

rosbag2 stores, for every topic, the full ``ros2msg`` definition of its type and its RIHS01 hash.
``rosbags`` ships the standard Jazzy types; types of other packages (``robotica_msgs``, a
user's) are registered from the ``.msg`` files found through the ament index.
:func:`message_class` finds the Python class of a type, to subscribe or publish it raw.
"""
import importlib
from pathlib import Path
from typing import Any

from ament_index_python.packages import get_package_share_directory, PackageNotFoundError
from rosbags.typesys import get_types_from_msg, get_typestore, Stores
from rosbags.typesys.store import Typestore


def jazzy_typestore() -> Typestore:
    """Return a fresh type store with the standard ROS 2 Jazzy message types."""
    return get_typestore(Stores.ROS2_JAZZY)


def ensure_type(typestore: Typestore, msgtype: str) -> None:
    """
    Register ``msgtype`` (``pkg/msg/Name``) and its package's messages if unknown.

    Raises KeyError when the package or its ``.msg`` file cannot be found.
    """
    if msgtype in typestore.fielddefs:
        return
    pkg, kind, name = msgtype.split('/')
    try:
        share = Path(get_package_share_directory(pkg))
    except PackageNotFoundError:
        raise KeyError(f'no package {pkg!r} in the ament index for type {msgtype}') from None
    types = {}
    for msg_file in sorted((share / kind).glob('*.msg')):
        types.update(get_types_from_msg(msg_file.read_text(), f'{pkg}/{kind}/{msg_file.stem}'))
    if msgtype not in types:
        raise KeyError(f'no definition of {msgtype} under {share / kind}')
    typestore.register(types)


def message_class(msgtype: str) -> Any:
    """
    Return the generated Python class of ``msgtype`` (``pkg/msg/Name``).

    Raises ValueError for a name not of that form, ImportError when the package is not
    installed, AttributeError when it has no such message.
    """
    package, kind, name = msgtype.split('/')
    return getattr(importlib.import_module(f'{package}.{kind}'), name)
