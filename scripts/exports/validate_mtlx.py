"""MaterialX's own checks of `woven export --format openpbr` documents.

    python scripts/exports/validate_mtlx.py FILE.mtlx...

For each document, with MaterialX's standard libraries loaded (`mx.loadLibraries` on the
installed package's `libraries/`, which define `open_pbr_surface` 1.1): `readFromXmlFile`, then
`doc.validate()`; every node must resolve to a node definition of those libraries (a misspelt
input or a wrong type does not), every `filename` input must name a file beside the document,
and MaterialX's GLSL generator must write the material's shader (the graph is one a renderer
can compile). Prints one line a document and exits 1 when any fails.
"""

import os
import sys

import MaterialX as mx
import MaterialX.PyMaterialXGenGlsl as mx_gen_glsl
import MaterialX.PyMaterialXGenShader as mx_gen_shader


def libraries():
    """MaterialX's standard data libraries, as a document."""
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    return lib


def problems(path, lib, generator):
    """What is wrong with the document at `path` (an empty list: nothing)."""
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, path)
    doc.setDataLibrary(lib)
    found = []
    ok, message = doc.validate()
    if not ok:
        found.append(f"validate(): {message.strip()}")
    for node in doc.getNodes():
        if node.getNodeDef() is None:
            found.append(f"node {node.getName()} ({node.getCategory()}, {node.getType()}) has no definition")
        for i in node.getInputs():
            if i.getType() == "filename":
                file = os.path.join(os.path.dirname(path), i.getValueString())
                if not os.path.isfile(file):
                    found.append(f"{node.getName()}.{i.getName()} names a missing file {file}")
    materials = doc.getMaterialNodes()
    if len(materials) != 1:
        found.append(f"{len(materials)} materials, expected 1")
    for m in materials:
        context = mx_gen_shader.GenContext(generator)
        context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
        try:
            shader = generator.generate(m.getName(), m, context)
            if not shader.getSourceCode(mx_gen_shader.PIXEL_STAGE):
                found.append(f"GLSL of {m.getName()}: empty pixel shader")
        except Exception as e:  # MaterialX raises its own exception types
            found.append(f"GLSL of {m.getName()}: {e}")
    return found


def main(paths):
    if not paths:
        print(__doc__)
        return 2
    lib = libraries()
    generator = mx_gen_glsl.GlslShaderGenerator.create()
    print(f"MaterialX {mx.getVersionString()}: {len(lib.getNodeDefs())} node definitions loaded")
    failed = 0
    for path in paths:
        found = problems(path, lib, generator)
        print(f"{path}: {'valid' if not found else 'INVALID'}")
        for p in found:
            print(f"  {p}")
        failed += bool(found)
    if failed:
        print(f"{failed} of {len(paths)} MaterialX documents fail", file=sys.stderr)
        return 1
    print(f"all {len(paths)} MaterialX documents pass (validate(), definitions, files, GLSL)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
