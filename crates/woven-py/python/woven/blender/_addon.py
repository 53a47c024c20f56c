"""The add-on's operator: Object → "Add woven material" on the active object. (No postponed
annotations here: Blender reads the properties from the class's evaluated annotations.)"""


import bpy


class WOVEN_OT_add_material(bpy.types.Operator):
    """Add a woven cloth material (its standard lobes laid out by the weave's textures)"""

    bl_idname = "woven.add_material"
    bl_label = "Add woven material"
    bl_options = {"REGISTER", "UNDO"}

    source: bpy.props.StringProperty(
        name="Material", default="polyester-sateen",
        description="A woven preset name or a material file (.toml)")
    pattern: bpy.props.StringProperty(
        name="Pattern", default="",
        description="A weave pattern replacing the material's: a name, or a WIF draft (.wif)")
    yarns_per_unit: bpy.props.FloatProperty(
        name="Yarns per metre", default=4000.0, min=1.0,
        description="Pattern cells per unit of the object's uv (threads per metre)")
    weft_color: bpy.props.FloatVectorProperty(
        name="Weft colour", subtype="COLOR", size=3, default=(0.6, 0.6, 0.6), min=0.0, max=1.0)
    warp_color: bpy.props.FloatVectorProperty(
        name="Warp colour", subtype="COLOR", size=3, default=(0.6, 0.6, 0.6), min=0.0, max=1.0)

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "MESH"

    def execute(self, context):
        from . import material

        keys = {"yarns_per_unit": self.yarns_per_unit, "weft_color": tuple(self.weft_color),
                "warp_color": tuple(self.warp_color)}
        if self.pattern.lower().endswith(".wif"):
            keys["pattern"] = {"wif": bpy.path.abspath(self.pattern)}
        elif self.pattern:
            keys["pattern"] = self.pattern
        try:
            mat = material(self.source, **keys)
        except (ValueError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        context.object.data.materials.append(mat)
        return {"FINISHED"}

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)


def _menu(self, context):
    self.layout.operator(WOVEN_OT_add_material.bl_idname)


def register():
    bpy.utils.register_class(WOVEN_OT_add_material)
    bpy.types.VIEW3D_MT_object.append(_menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(_menu)
    bpy.utils.unregister_class(WOVEN_OT_add_material)
