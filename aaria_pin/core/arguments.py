"""The front door's argument checks: a wrong type is our error, naming the parameter.

:func:`checked` decorates a public function (or an input class: its ``__init__``) and checks each
argument it is given against the parameter's annotation, before the function runs. A wrong type
raises :class:`~aaria_pin.errors.ParameterTypeError` (a ``ParameterError`` that is also a
``TypeError``) naming the parameter, in one line: ``duration is '1' (str); allowed: a number``.
What the annotations say is checked, and no more:

- ``bool`` is True or False (NumPy's too), and is not a number; ``int`` an integer; ``float`` a
  finite real number (an integer too);
- ``str`` text; ``os.PathLike`` and ``Path`` a path or text;
- ``ArrayLike`` and ``Array`` numbers NumPy makes an array of, never text, booleans or objects
  (a :class:`~aaria_pin.errors.TableTypeError`, also a ``TableError``; a ragged nesting is a bad
  value, a ``ParameterError``);
- a class: an instance of it; a ``Protocol``: an object with the protocol's members; ``Literal``
  values: the type of one of them; ``Sequence``, ``tuple``, ``Mapping`` and ``dict`` with their
  items; ``Callable`` anything callable; a union: one of its members; ``Any``: anything;
- keyword options typed ``**options: Unpack[SomeTypedDict]`` by the dictionary's keys; a missing
  required argument or an unknown keyword is a ``ParameterTypeError`` too.

A ``float`` must also be finite (NaN or inf is a ``ParameterError``, not a ``TypeError``); other
values stay the function's to check (a range, a shape, NaN in an array: each function says what it
allows, as a ``ParameterError``). Arguments are passed on as given. The annotations are read with
:func:`typing.get_type_hints` at the first call, so decorating costs nothing at import; a name
its module imports only for type checkers (``if TYPE_CHECKING:``) is imported then, and one that
cannot be found is not checked.

Overhead, measured (``timeit`` on a shared 2-core machine): 1 to 3 µs an argument (a number, a
small array, a robot checked against its protocol; a protocol's members are looked up once per
class), so :func:`~aaria_pin.core.run.simulate` of a robot and its settings checks in about 7 µs,
against about 2 ms for the run itself (1 s at 100 Hz, the Aaria arm): 0.4 %.
"""

from __future__ import annotations

import functools
import math
import numbers
import os
import sys
import typing
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import PurePath
from types import FunctionType, NoneType, UnionType
from typing import Any, TypeVar

from aaria_pin.errors import ParameterError, ParameterTypeError, TableTypeError

__all__ = ["checked"]

F = TypeVar("F", bound=Callable[..., Any])

Accepts = Callable[[Any, str], bool]
"""Whether a value is of a kind (a value of the kind that is bad raises a ``ParameterError``)."""


@dataclass(frozen=True)
class _Kind:
    """One kind an annotation allows: its test and how a message names it."""

    accepts: Accepts
    allowed: str
    error: type[ParameterTypeError] = ParameterTypeError


def checked(target: F) -> F:
    """Check the types of the arguments of a public function, or of an input class's ``__init__``.

    Args:
        target: the function or class (its annotations say what each parameter takes)

    Returns:
        The function, wrapped (the class, its ``__init__`` wrapped), with the same signature.

    Raises:
        ParameterTypeError: (when the wrapped function is called) an argument of a type its
            annotation does not allow, a missing required argument, an unknown keyword.
        ParameterError: an array argument that is a ragged nesting.
    """
    if isinstance(target, type):
        target.__init__ = _wrapped(target.__init__)  # type: ignore[misc]
        return target
    return typing.cast(F, _wrapped(target))


def _wrapped(function: Callable[..., Any]) -> Callable[..., Any]:
    plan: list[_Plan] = []
    build = _Plan.of

    def call(*args: Any, **kwargs: Any) -> Any:
        if not plan:
            plan.append(build(function))
        plan[0].check(args, kwargs)
        return function(*args, **kwargs)

    # The wrapper runs in the function's own module (it reads only its closure), so a trace of
    # the calls sees the function's layer call the function, not the core call up into it.
    scope = getattr(function, "__globals__", None)
    if scope is not None:
        call = FunctionType(call.__code__, scope, call.__name__, None, call.__closure__)
    return functools.wraps(function)(call)


@dataclass(frozen=True)
class _Plan:
    """What a function's parameters take, read once from its signature and annotations."""

    name: str
    positional: tuple[tuple[str, _Kind | None], ...]
    keyword: dict[str, _Kind | None]
    required: tuple[tuple[int, str], ...]
    more_positional: bool
    more_keywords: bool

    @classmethod
    def of(cls, function: Callable[..., Any]) -> _Plan:
        import inspect  # here, not at import: the command line starts without it

        hints = _hints(function)
        positional: list[tuple[str, _Kind | None]] = []
        keyword: dict[str, _Kind | None] = {}
        required: list[tuple[int, str]] = []
        more_positional = more_keywords = False
        for index, parameter in enumerate(inspect.signature(function).parameters.values()):
            kind = _kind(hints.get(parameter.name, Any))
            if parameter.kind is parameter.VAR_POSITIONAL:
                more_positional = True
            elif parameter.kind is parameter.VAR_KEYWORD:
                options = _options(hints.get(parameter.name))
                more_keywords = options is None
                keyword.update({key: _kind(hint) for key, hint in (options or {}).items()})
            else:
                if parameter.kind is not parameter.KEYWORD_ONLY:
                    positional.append((parameter.name, kind))
                if parameter.kind is not parameter.POSITIONAL_ONLY:
                    keyword[parameter.name] = kind
                if parameter.default is parameter.empty:
                    at = index if parameter.kind is not parameter.KEYWORD_ONLY else sys.maxsize
                    required.append((at, parameter.name))
        name = getattr(function, "__qualname__", "the function").removesuffix(".__init__")
        return cls(
            name, tuple(positional), keyword, tuple(required), more_positional, more_keywords
        )

    def check(self, args: tuple[Any, ...], kwargs: dict[str, Any]) -> None:
        """Check a call's arguments (see :func:`checked`)."""
        for value, (name, kind) in zip(args, self.positional, strict=False):
            if kind is not None and not kind.accepts(value, name):
                raise _type_error(name, value, kind)
        if len(args) > len(self.positional) and not self.more_positional:
            raise ParameterTypeError(
                f"{self.name} takes {len(self.positional)} positional arguments, given "
                f"{len(args)}; allowed: the others by keyword",
                parameter=self.positional[-1][0] if self.positional else None,
            )
        for name, value in kwargs.items():
            kind = self.keyword.get(name, _UNKNOWN)
            if kind is _UNKNOWN:
                if not self.more_keywords:
                    raise ParameterTypeError(
                        f"{self.name} got an unexpected keyword argument {name!r}; allowed: "
                        + ", ".join(self.keyword),
                        parameter=name,
                    )
            elif kind is not None and not kind.accepts(value, name):
                raise _type_error(name, value, kind)
        for at, name in self.required:
            if at >= len(args) and name not in kwargs:
                raise ParameterTypeError(
                    f"{name} is missing; allowed: a value (it is required)", parameter=name
                )


_UNKNOWN = _Kind(lambda value, name: True, "")
"""A keyword the function does not take."""


def _type_error(name: str, value: Any, kind: _Kind, element: str = "") -> ParameterTypeError:
    allowed = kind.allowed
    where = f"{element} of {name}" if element else name
    return kind.error(
        f"{where} is {_described(value)}; allowed: {allowed}",
        parameter=name,
        value=value,
        allowed=allowed,
        element=element or None,
    )


def _described(value: Any) -> str:
    """A value in a message, one line: a short value and its type, or its type alone."""
    if value is None or isinstance(value, bool):
        return str(value)
    if isinstance(value, int | float):
        return f"{value!r} ({type(value).__name__})"
    if isinstance(value, str):
        return repr(value if len(value) <= 40 else value[:37] + "...") + " (str)"
    dtype = getattr(value, "dtype", None)
    if dtype is not None and hasattr(value, "shape"):
        shape = " × ".join(map(str, value.shape)) or "0-d"
        return f"an array of {dtype} (shape {shape})"
    noun = type(value).__name__
    return f"{'an' if noun[:1].lower() in 'aeiou' else 'a'} {noun}"


def _hints(function: Callable[..., Any]) -> dict[str, Any]:
    """The function's annotations as objects; a name that cannot be found is left out.

    A name its module imports only for type checkers (``if TYPE_CHECKING:``) is imported now.
    """
    try:
        return typing.get_type_hints(function)
    except NameError:
        module = sys.modules.get(getattr(function, "__module__", ""))
        scope = {**_type_checking_names(module), **getattr(function, "__globals__", {})}
        return {
            name: hint
            for name, text in getattr(function, "__annotations__", {}).items()
            if (hint := _resolved(text, scope)) is not None
        }


def _type_checking_names(module: Any) -> dict[str, Any]:
    """The names a module imports in its ``if TYPE_CHECKING:`` block, imported."""
    import ast
    import importlib
    import inspect

    try:
        tree = ast.parse(inspect.getsource(module))
    except (OSError, TypeError):
        return {}
    names: dict[str, Any] = {}
    for node in tree.body:
        test = node.test if isinstance(node, ast.If) else None
        if not (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING"):
            continue
        for statement in typing.cast(ast.If, node).body:
            if isinstance(statement, ast.ImportFrom) and statement.module and not statement.level:
                try:
                    source = importlib.import_module(statement.module)
                except ImportError:  # an optional dependency: its names stay unchecked
                    continue
                for alias in statement.names:
                    if hasattr(source, alias.name):
                        names[alias.asname or alias.name] = getattr(source, alias.name)
    return names


def _resolved(text: Any, scope: dict[str, Any]) -> Any:
    if not isinstance(text, str):
        return text
    try:
        return eval(text, dict(scope))  # the function's own annotation, in its module
    except NameError:
        return None


def _options(hint: Any) -> dict[str, Any] | None:
    """The keys of ``**options: Unpack[SomeTypedDict]`` and their hints (None: any keyword)."""
    if typing.get_origin(hint) is not typing.Unpack:
        return None
    (options,) = typing.get_args(hint)
    try:
        return typing.get_type_hints(options)
    except NameError:
        found = {}
        for key, reference in options.__annotations__.items():
            module = getattr(reference, "__forward_module__", None) or options.__module__
            scope = {**_type_checking_names(sys.modules[module]), **vars(sys.modules[module])}
            found[key] = _resolved(getattr(reference, "__forward_arg__", reference), scope)
        return {key: hint for key, hint in found.items() if hint is not None}


def _kind(hint: Any) -> _Kind | None:
    """The test of what an annotation allows (None: anything)."""
    origin = typing.get_origin(hint)
    members = typing.get_args(hint)
    if origin in (typing.Union, UnionType):
        if _is_array_like(members):
            rest = [m for m in members if m is NoneType]
            kinds = [_array_kind(), *(_kind(m) for m in rest)]
        else:
            kinds = [_kind(member) for member in members]
        if any(kind is None for kind in kinds):
            return None
        return _union([kind for kind in kinds if kind is not None])
    if origin is typing.Literal:
        types = tuple({type(member) for member in members})
        shown = ", ".join(repr(member) for member in members)
        return _Kind(lambda value, name: isinstance(value, types), f"one of {shown}")
    if origin is not None:
        return _generic_kind(origin, members)
    return _plain_kind(hint)


def _union(kinds: list[_Kind]) -> _Kind:
    if len(kinds) == 1:
        return kinds[0]

    def accepts(value: Any, name: str) -> bool:
        return any(kind.accepts(value, name) for kind in kinds)

    error = next((kind.error for kind in kinds if kind.error is not ParameterTypeError), None)
    return _Kind(accepts, " or ".join(kind.allowed for kind in kinds), error or ParameterTypeError)


def _is_array_like(members: tuple[Any, ...]) -> bool:
    """Whether a union is NumPy's ``ArrayLike`` (or it and None)."""
    names = {getattr(member, "__name__", "") for member in members}
    return {"_SupportsArray", "_NestedSequence"} <= names or "_Buffer" in names


def _plain_kind(hint: Any) -> _Kind | None:
    kinds: dict[Any, _Kind] = {
        NoneType: _Kind(lambda value, name: value is None, "None"),
        bool: _Kind(lambda value, name: _is_bool(value), "True or False"),
        int: _Kind(
            lambda value, name: isinstance(value, numbers.Integral) and not _is_bool(value),
            "an integer",
        ),
        float: _Kind(_finite_number, "a number"),
        str: _Kind(lambda value, name: isinstance(value, str), "text (str)"),
    }
    if hint in kinds:
        return kinds[hint]
    if hint is typing.Any or isinstance(hint, TypeVar) or hint is object:
        return None
    if hint in (os.PathLike, PurePath) or (isinstance(hint, type) and issubclass(hint, PurePath)):
        return _Kind(lambda value, name: isinstance(value, str | os.PathLike), "a path")
    if hint is Callable:
        return _Kind(lambda value, name: callable(value), "a callable")
    if isinstance(hint, type):
        if getattr(hint, "_is_protocol", False):
            return _protocol_kind(hint)
        if hint.__module__ == "numpy" and hint.__name__ == "ndarray":
            return _array_kind()
        article = "an" if hint.__name__[:1].lower() in "aeiou" else "a"
        return _Kind(lambda value, name: isinstance(value, hint), f"{article} {hint.__name__}")
    return None


def _generic_kind(origin: Any, members: tuple[Any, ...]) -> _Kind | None:
    """``Sequence[X]``, ``tuple[X, ...]``, ``Mapping[K, V]``, ``os.PathLike[str]``, ``ndarray``."""
    if origin is os.PathLike:
        return _plain_kind(os.PathLike)
    if origin is typing.ClassVar:
        return None
    if isinstance(origin, type) and origin.__name__ == "ndarray":
        return _array_kind()
    if origin is Callable or origin is type:
        return _plain_kind(origin) if origin is Callable else None
    if isinstance(origin, type) and issubclass(origin, Mapping):
        keys, values = (_kind(member) for member in (members or (Any, Any)))
        return _Kind(_items(Mapping, keys, values), "a mapping")
    if isinstance(origin, type) and issubclass(origin, Sequence):
        uniform = members and (len(members) == 1 or members[1:] == (...,))
        item = _kind(members[0]) if uniform else None
        shown = f" of {item.allowed}" if item else ""
        return _Kind(_items(Sequence, None, item), f"a sequence{shown}")
    return _plain_kind(origin)


def _items(container: type, keys: _Kind | None, values: _Kind | None) -> Accepts:
    """A container whose keys and items (or values) are of their kinds."""

    def accepts(value: Any, name: str) -> bool:
        if not isinstance(value, container) or isinstance(value, str | bytes):
            return False
        given: Any = value
        pairs = given.items() if isinstance(given, Mapping) else enumerate(given)
        for key, item in pairs:
            for part, kind, what in ((key, keys, "key"), (item, values, "item")):
                if kind is not None and not kind.accepts(part, name):
                    element = f"{what} {key!r}" if isinstance(value, Mapping) else f"item {key}"
                    raise _type_error(name, part, kind, element)
        return True

    return accepts


def _protocol_kind(protocol: type) -> _Kind:
    """An object with every member of a protocol (a method, a property or an attribute)."""
    members = sorted(
        {
            name
            for base in protocol.__mro__
            if getattr(base, "_is_protocol", False) and base is not typing.Protocol
            for name in (*vars(base), *getattr(base, "__annotations__", {}))
            if not name.startswith("_")
        }
    )
    known: set[type] = set()

    def accepts(value: Any, name: str) -> bool:
        kind = type(value)
        if kind in known:
            return True
        own = getattr(value, "__dict__", {})  # read, never call, a property
        on_class = [hasattr(kind, member) for member in members]
        if all(on_class):
            known.add(kind)
        return all(
            found or member in own or hasattr(value, member)  # the last: a __getattr__
            for found, member in zip(on_class, members, strict=True)
        )

    return _Kind(accepts, f"a {protocol.__name__}")


def _finite_number(value: Any, name: str) -> bool:
    """A real number (an integer too, not a boolean); NaN or inf is a bad value."""
    if not isinstance(value, numbers.Real) or _is_bool(value):
        return False
    if not math.isfinite(value):
        raise ParameterError(parameter=name, value=value, allowed="a finite number")
    return True


def _is_bool(value: Any) -> bool:
    return isinstance(value, bool) or (type(value).__name__ == "bool" and hasattr(value, "dtype"))


def _array_kind() -> _Kind:
    """Numbers NumPy makes an array of (not text, booleans, objects or complex numbers)."""

    def accepts(value: Any, name: str) -> bool:
        if value is None or isinstance(value, str | bytes | Mapping):
            return False
        import numpy as np

        try:
            array = np.asarray(value)
        except (ValueError, TypeError) as error:  # a ragged nesting
            raise ParameterError(
                f"{name} is a ragged nesting of sequences; allowed: a numeric array",
                parameter=name,
                allowed="a numeric array",
            ) from error
        return array.dtype.kind in "iuf"

    return _Kind(accepts, "a numeric array", TableTypeError)
