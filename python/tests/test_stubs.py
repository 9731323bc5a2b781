"""The type stubs (splineskin/_splineskin.pyi) name exactly what the extension module has: every
class with its methods and properties, every function, and their parameters."""

from __future__ import annotations

import ast
import inspect
import sys
from pathlib import Path

import splineskin
from splineskin import _splineskin

STUBS = Path(splineskin.__file__).with_name("_splineskin.pyi")


def stub_tree():
    classes, functions = {}, {}
    for node in ast.parse(STUBS.read_text()).body:
        if isinstance(node, ast.ClassDef):
            members = {}
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members[item.name] = [a.arg for a in item.args.posonlyargs + item.args.args + item.args.kwonlyargs]
            classes[node.name] = members
        elif isinstance(node, ast.FunctionDef):
            functions[node.name] = [a.arg for a in node.args.posonlyargs + node.args.args + node.args.kwonlyargs]
    return classes, functions


def runtime_parameters(obj) -> list[str]:
    return [p for p in inspect.signature(obj).parameters]


def test_every_class_and_member_is_in_the_stubs_and_the_stubs_name_nothing_else():
    classes, functions = stub_tree()
    runtime_classes = {n for n, v in vars(_splineskin).items() if isinstance(v, type) and n != "SplineSkinError"}
    assert set(classes) - {"SplineSkinError"} == runtime_classes
    for name, members in classes.items():
        if name == "SplineSkinError":
            continue
        cls = getattr(_splineskin, name)
        public = {m for m in dir(cls) if not m.startswith("_")}
        assert set(members) - {"__init__"} == public, name
        for member, params in members.items():
            if member == "__init__":
                # Under the stable ABI (the abi3 wheel), Python reads a class's constructor
                # signature only from 3.10 on; its methods' signatures it reads on every version.
                if sys.version_info >= (3, 10):
                    assert runtime_parameters(cls) == [p for p in params if p != "self"], f"{name}()"
                continue
            attribute = inspect.getattr_static(cls, member)
            if isinstance(attribute, (staticmethod, classmethod)):
                assert runtime_parameters(getattr(cls, member)) == params, f"{name}.{member}"
            elif callable(attribute):
                assert runtime_parameters(attribute) == params, f"{name}.{member}"
    runtime_functions = {n for n, v in vars(_splineskin).items() if callable(v) and not isinstance(v, type)}
    assert set(functions) == runtime_functions
    for name, params in functions.items():
        assert runtime_parameters(getattr(_splineskin, name)) == params, name
