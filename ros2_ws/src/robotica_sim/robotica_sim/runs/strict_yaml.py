"""
The one strict reader of the YAML files a user writes: scenarios and rubrics.

:func:`read_strict_yaml` returns the document of a small UTF-8 file, or raises the caller's
error class with one line naming the file and the reason. It refuses what ``yaml.safe_load``
lets through silently or slowly: a key given twice in a mapping (the last one would win), a
file larger than :data:`MAX_FILE_SIZE` (``/dev/zero`` would be read for ever), bytes that are
not UTF-8, a document of more than :data:`MAX_VALUES` values once its aliases are expanded
(a few hundred bytes can hold 1e9). Numbers are read as YAML 1.2 reads them: ``1e3`` and
``-2E-4`` are floats (YAML 1.1, PyYAML's default, makes them strings without a dot).
"""
from pathlib import Path
import re
from typing import Any

import yaml

__all__ = ['MAX_FILE_SIZE', 'MAX_VALUES', 'read_strict_yaml']

MAX_FILE_SIZE = 1_000_000           # [bytes] of a scenario or rubric file
MAX_VALUES = 1_000_000              # keys, values and list items of a document


class _StrictLoader(yaml.SafeLoader):
    """A safe YAML loader that refuses a key given twice in a mapping (else the last wins)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        """Return the mapping of ``node``; ConstructorError for a key given twice."""
        self.flatten_mapping(node)   # merge keys (<<) first, as SafeLoader does
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            if isinstance(key, (str, int, float, bool)) or key is None:
                if key in seen:
                    raise yaml.constructor.ConstructorError(
                        None, None, f'key {key!r} given twice',
                        key_node.start_mark)
                seen.add(key)
        return super().construct_mapping(node, deep)


# YAML 1.2 floats without a dot (1e3, -2E-4), which YAML 1.1 leaves as strings.
_StrictLoader.add_implicit_resolver('tag:yaml.org,2002:float',
                                    re.compile(r'^[-+]?[0-9]+[eE][-+]?[0-9]+$'),
                                    list('-+0123456789'))


def read_strict_yaml(path: str | Path, error: type[Exception]) -> Any:
    r"""
    Return the YAML document of the small UTF-8 file ``path``, or raise ``error`` in one line.

    Refused: a file that cannot be read, larger than :data:`MAX_FILE_SIZE`, not UTF-8 text,
    not YAML, with a key given twice in a mapping, or of more than :data:`MAX_VALUES` values
    once its aliases are expanded.

    >>> import tempfile
    >>> with tempfile.NamedTemporaryFile('w', suffix='.yaml') as f:
    ...     _ = f.write('a: 1e3\nb: 10\n'); f.flush()
    ...     read_strict_yaml(f.name, ValueError)
    {'a': 1000.0, 'b': 10}
    """
    try:
        with open(path, 'rb') as file:
            raw = file.read(MAX_FILE_SIZE + 1)
    except OSError as err:
        raise error(f'{path}: cannot read: {err.strerror or err}') from None
    if len(raw) > MAX_FILE_SIZE:
        raise error(f'{path}: larger than {MAX_FILE_SIZE} bytes')
    try:
        text = raw.decode('utf-8')
    except UnicodeDecodeError as err:
        raise error(f'{path}: not a text file (not UTF-8: byte 0x{raw[err.start]:02x} '
                    f'at offset {err.start})') from None
    try:
        data = yaml.load(text, Loader=_StrictLoader)
    except yaml.YAMLError as err:
        mark = getattr(err, 'problem_mark', None)
        where = f' at line {mark.line + 1}, column {mark.column + 1}' if mark else ''
        reason = getattr(err, 'problem', None) or str(err)
        raise error(f'{path}: not valid YAML{where}: {" ".join(reason.split())}') from None
    except RecursionError:
        raise error(f'{path}: nested too deeply') from None
    if _too_many_values(data, MAX_VALUES):
        raise error(f'{path}: more than {MAX_VALUES} values (YAML aliases?)')
    return data


def _too_many_values(data: Any, budget: int) -> bool:
    """Return whether ``data`` holds more than ``budget`` values, aliases counted each time."""
    stack, count = [data], 0
    while stack:
        item = stack.pop()
        count += 1
        if count > budget:
            return True
        if isinstance(item, dict):
            stack.extend(item.keys())
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
    return False
