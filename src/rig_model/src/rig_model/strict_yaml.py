"""Strict reading of the project's YAML files from Python, as rig_model/strict_yaml.h does in C++.

Every error is a FileError whose message names the file, and where it can the line and the key:
"camera_imu.yaml:4: unknown key 'camera_imu.rotaton_xyzw' (did you mean 'rotation_xyzw'?)".
"""
import difflib
import math

import yaml


class FileError(Exception):
    """A file that cannot be used; str() names the file, line and field."""


class _Map(dict):
    """A YAML mapping that remembers the line (1-based) of itself and of each key."""
    line = None
    key_lines = None


class _Loader(yaml.SafeLoader):
    def construct_mapping(self, node, deep=False):
        seen = {}
        for k, _ in node.value:  # PyYAML keeps the last of two equal keys, yaml-cpp the first: refuse both
            if isinstance(k, yaml.ScalarNode):
                if k.value in seen:
                    raise yaml.constructor.ConstructorError(
                        None, None, "duplicate key '%s' (first at line %d)" % (k.value, seen[k.value]), k.start_mark)
                seen[k.value] = k.start_mark.line + 1
        m = _Map(super().construct_mapping(node, deep=deep))
        m.line = node.start_mark.line + 1
        m.key_lines = {self.construct_object(k, deep=True): k.start_mark.line + 1 for k, _ in node.value
                       if isinstance(k, yaml.ScalarNode)}
        return m


_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _Loader.construct_mapping)


def field_path(where, key):
    return "%s.%s" % (where, key) if where else key


def nearest_key(key, candidates):
    """The candidate closest to key, or "" when none is close enough to be a typo."""
    close = difflib.get_close_matches(str(key), list(candidates), n=1, cutoff=0.6)
    return close[0] if close else ""


def load_yaml_file(path):
    """The parsed file. Raises FileError naming the file when it cannot be read, is not UTF-8
    text, or does not parse (with the parser's line)."""
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise FileError("%s: cannot open the file (%s)" % (path, e.strerror)) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise FileError("%s: not a text file (invalid UTF-8 at byte %d); expected YAML" % (path, e.start)) from None
    try:
        return yaml.load(text, Loader=_Loader)
    except yaml.MarkedYAMLError as e:
        line = e.problem_mark.line + 1 if e.problem_mark else "?"
        raise FileError("%s:%s: not valid YAML: %s" % (path, line, e.problem)) from None
    except yaml.YAMLError as e:
        raise FileError("%s: not valid YAML: %s" % (path, e)) from None


def line_of(node, key=None):
    """The line of key in mapping node (or of the node itself), "?" when unknown."""
    if isinstance(node, _Map):
        if key is not None and key in node.key_lines:
            return node.key_lines[key]
        return node.line
    return "?"


def fail(path, node, field, what, key=None):
    raise FileError("%s:%s: %s: %s" % (path, line_of(node, key), field, what))


def check_keys(path, node, known, where=""):
    """Raises FileError unless node is a mapping whose keys are all in known."""
    if not isinstance(node, dict):
        fail(path, node, where or "the file", "must be a mapping of key: value")
    for key in node:
        if key in known:
            continue
        message = "%s:%s: unknown key '%s'" % (path, line_of(node, key), field_path(where, key))
        nearest = nearest_key(key, known)
        if nearest:
            message += " (did you mean '%s'?)" % nearest
        else:
            message += "; known keys: " + ", ".join(known)
        raise FileError(message)


def numbers(path, node, where, key, count, default=None):
    """A list of `count` finite numbers at where.key; default when absent (required if None)."""
    if key not in node:
        if default is None:
            fail(path, node, field_path(where, key), "is missing")
        return list(default)
    v = node[key]
    ok = isinstance(v, list) and len(v) == count and all(
        isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in v)
    if not ok:
        fail(path, node, field_path(where, key), "must be a list of %d finite numbers, got %r" % (count, v), key)
    return [float(x) for x in v]


def string(path, node, where, key, default):
    """A non-empty string at where.key, or default when absent."""
    if key not in node:
        return default
    v = node[key]
    if not isinstance(v, str) or not v:
        fail(path, node, field_path(where, key), "must be a non-empty string, got %r" % (v,), key)
    return v
