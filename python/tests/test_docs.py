"""What a reader and an editor see: help() that documents every parameter,
type stubs (__init__.pyi) that match the module, name for name and argument
for argument."""
import ast
import inspect
import pathlib
import pydoc

import pytest

import glint

STUB = pathlib.Path(glint.__file__).with_name("__init__.pyi")
PUBLIC_CLASSES = ["Scene", "Render", "CancelToken", "SceneError", "Material", "Light", "Object", "Camera",
                  "RenderSettings", "Materials", "Lights", "Objects"]
PUBLIC_FUNCTIONS = ["load", "loads", "render", "explain", "read_image", "write_image"]


@pytest.fixture(scope="module")
def stub():
    return ast.parse(STUB.read_text())


def stub_defs(body):
    """name -> list of FunctionDef (overloads give several) and name -> ClassDef."""
    functions, classes, names = {}, {}, set()
    for node in body:
        if isinstance(node, ast.FunctionDef):
            functions.setdefault(node.name, []).append(node)
        elif isinstance(node, ast.ClassDef):
            classes[node.name] = node
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets)
    return functions, classes, names


def stub_params(f):
    a = f.args
    return ([(p.arg, "positional") for p in a.posonlyargs + a.args] + ([("*" + a.vararg.arg, "var")] if a.vararg else [])
            + [(p.arg, "keyword") for p in a.kwonlyargs] + ([("**" + a.kwarg.arg, "var")] if a.kwarg else []))


def runtime_params(f):
    out = []
    for p in inspect.signature(f).parameters.values():
        if p.kind == p.VAR_POSITIONAL:
            out.append(("*" + p.name, "var"))
        elif p.kind == p.VAR_KEYWORD:
            out.append(("**" + p.name, "var"))
        else:
            out.append((p.name, "keyword" if p.kind == p.KEYWORD_ONLY else "positional"))
    return out


def test_all_names_the_public_api():
    assert sorted(glint.__all__) == sorted(PUBLIC_CLASSES + PUBLIC_FUNCTIONS + ["embree_available", "PASSES",
                                                                                "__version__"])
    for name in glint.__all__:
        assert hasattr(glint, name), name


def test_the_stubs_declare_every_public_name_with_the_modules_arguments(stub):
    functions, classes, names = stub_defs(stub.body)
    assert {"__version__", "PASSES", "embree_available"} <= names
    for name in PUBLIC_FUNCTIONS:
        assert name in functions, name
        for overload in functions[name]:
            assert stub_params(overload) == runtime_params(getattr(glint, name)), name
    for name in PUBLIC_CLASSES:
        assert name in classes, name
        runtime = getattr(glint, name)
        s_functions, _, s_names = stub_defs(classes[name].body)
        public = [m for m, v in vars(runtime).items()
                  if not m.startswith("_") and (inspect.isfunction(v) or isinstance(v, (property, classmethod)))]
        for m in public:
            assert m in s_functions or m in s_names, f"{name}.{m} is not in the stubs"
            v = vars(runtime)[m]
            if inspect.isfunction(v) or isinstance(v, classmethod):
                params = [p for p in runtime_params(getattr(runtime, m)) if p[0] not in ("self", "cls")]
                stub_p = [p for p in stub_params(s_functions[m][0]) if p[0] not in ("self", "cls")]
                assert stub_p == params, f"{name}.{m}"
        # The views' fields are the stub's attributes, in the same order.
        fields = getattr(runtime, "_fields", ())
        if fields:
            annotated = [n.target.id for n in classes[name].body if isinstance(n, ast.AnnAssign)]
            assert annotated == list(fields), name


def test_help_documents_every_parameter():
    for f in [glint.render, glint.explain, glint.load, glint.loads, glint.read_image, glint.write_image,
              glint.Scene.add_mesh, glint.Scene.from_dict, glint.Render.save]:
        doc = inspect.getdoc(f)
        assert doc and len(doc) > 80, f.__qualname__
        for p in inspect.signature(f).parameters:
            if p not in ("self", "cls"):
                assert p in doc, f"{f.__qualname__}: {p} is not documented"
    for name in PUBLIC_CLASSES:
        assert inspect.getdoc(getattr(glint, name)), name
        for m, v in vars(getattr(glint, name)).items():
            if not m.startswith("_") and (inspect.isfunction(v) or isinstance(v, property)):
                assert inspect.getdoc(v), f"{name}.{m} has no docstring"
    text = pydoc.render_doc(glint.render, renderer=pydoc.plaintext)
    assert text.count("render(scene: glint.Scene, *, width: Optional[int] = None") == 1 and "KeyboardInterrupt" in text
    assert "glint" in pydoc.render_doc(glint, renderer=pydoc.plaintext)
