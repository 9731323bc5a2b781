#!/usr/bin/env python3
"""Puppet Warp for Inkscape: pins dropped on the selected art, moved and turned with Inkscape's
own tools, and "Apply" deforms the art with splineskin so that each pin's art follows it, keeping
the art Bézier curves with its ids, styles and structure.

The document keeps what a warp needs:

- each pin is a group ``<g splineskin:rest="x y">`` in the layer "Puppet Warp pins": its rest
  position (root user units) and, in its transform as Inkscape writes it when the pin is moved,
  turned or scaled, the pin's affine map;
- the rest of every warped element (and of every gradient or pattern a warp changed) is kept as
  text in ``<metadata><splineskin:puppet-warp>``, so that applying again starts from the rest
  drawing, and "Restore rest" puts it back.

Apply runs splineskin (``SplineRig.to_svg``, what ``splineskin deform`` writes) on a copy of the
document holding only the warped elements, their groups and the definitions, and puts the
deformed elements back in place by id.
"""

from __future__ import annotations

import os
import sys
import tempfile

# splineskin installed beside this script (`pip install --target lib …`, README.md) when the
# Python Inkscape runs has no splineskin of its own.
sys.path.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "lib"))

import inkex  # noqa: E402
from lxml import etree  # noqa: E402

NAMESPACE = "https://github.com/splineskin/splineskin/ns/puppet-warp"
inkex.NSS["splineskin"] = NAMESPACE

REST = inkex.addNS("rest", "splineskin")
ROLE = inkex.addNS("role", "splineskin")
STORE = inkex.addNS("puppet-warp", "splineskin")
KEPT = inkex.addNS("kept", "splineskin")
ADDED = inkex.addNS("added", "splineskin")
# Elements a warp may change in place: paint servers and other resources, replaced as a whole.
RESOURCE_TAGS = {
    inkex.addNS(t, "svg")
    for t in ("linearGradient", "radialGradient", "pattern", "marker", "clipPath", "mask", "filter")
}
PINS_LABEL = "Puppet Warp pins"
# A pin's marker radius, as a share of the page's diagonal.
PIN_SIZE = 0.008
# Elements a warped copy of the document keeps whatever is selected: definitions and metadata.
KEPT_TAGS = {inkex.addNS(t, "svg") for t in ("defs", "metadata", "style")} | {
    inkex.addNS("namedview", "sodipodi")
}


def splineskin_module():
    """The splineskin package, or an error saying how to install it."""
    try:
        import splineskin
    except ImportError as e:
        raise inkex.AbortExtension(
            "Puppet Warp needs the splineskin Python package, which the Python running Inkscape's "
            f"extensions ({sys.executable}) cannot import ({e}). Install it for that Python "
            "(pip install splineskin-…whl), or into this extension's folder: "
            f"pip install --target \"{os.path.join(os.path.dirname(os.path.abspath(__file__)), 'lib')}\" "
            "splineskin-…whl"
        ) from e
    return splineskin


class PuppetWarp(inkex.EffectExtension):
    """One extension, three actions (the .inx files set ``--action``)."""

    def add_arguments(self, pars):
        pars.add_argument("--action", default="apply", choices=["add_pin", "apply", "restore"])
        pars.add_argument("--tab", default="")
        pars.add_argument("--pin_at", default="selection", choices=["selection", "point"])
        pars.add_argument("--x", type=float, default=0.0)
        pars.add_argument("--y", type=float, default=0.0)
        pars.add_argument("--weights", default="bbw", choices=["bbw", "harmonic", "biharmonic", "shepard"])
        pars.add_argument("--stiffness", type=float, default=2.0)
        pars.add_argument("--expansion", type=float, default=1.0)

    def effect(self):
        {"add_pin": self.add_pins, "apply": self.apply, "restore": self.restore}[self.options.action]()
        # Our attributes written with the prefix `splineskin`, declared once on the root.
        etree.cleanup_namespaces(self.document, top_nsmap={
            "splineskin": NAMESPACE, "inkscape": inkex.NSS["inkscape"], "sodipodi": inkex.NSS["sodipodi"]})

    # ---- pins

    def pins_layer(self, create: bool):
        """The layer holding the pins, created on top of the drawing when asked."""
        for layer in self.svg:
            if isinstance(layer.tag, str) and layer.get(ROLE) == "pins":
                return layer
        if not create:
            return None
        layer = self.svg.add(inkex.Layer.new(PINS_LABEL))
        layer.set(ROLE, "pins")
        return layer

    def pins(self):
        """The pins: ``[(group, (x, y) at rest)]`` in the order they were added."""
        layer = self.pins_layer(create=False)
        if layer is None:
            return []
        found = []
        for group in layer.iterdescendants():
            rest = group.get(REST)
            if rest is None:
                continue
            try:
                x, y = (float(v) for v in rest.split())
            except ValueError:
                raise inkex.AbortExtension(
                    f"Puppet Warp: pin {group.get_id()}: its rest position splineskin:rest=\"{rest}\" "
                    "is not two numbers (was it edited by hand?)"
                )
            found.append((group, (x, y)))
        return found

    def add_pins(self):
        if self.options.pin_at == "point":
            positions = [(self.options.x, self.options.y)]
        else:
            positions = self.selection_centres()
            if not positions:
                raise inkex.AbortExtension(
                    "Puppet Warp: select the art to pin (a pin goes at the centre of each selected "
                    "object), or choose \"at a point\" and give its position"
                )
        layer = self.pins_layer(create=True)
        x0, y0, width, height = self.svg.get_viewbox()
        radius = PIN_SIZE * ((width or 100.0) ** 2 + (height or 100.0) ** 2) ** 0.5
        for x, y in positions:
            self.add_pin(layer, x, y, radius)

    def selection_centres(self):
        """The centre of each selected object's bounding box (root user units). inkex's
        bounding boxes write the transforms they read back rounded to six digits: the art's
        attributes are put back as they were."""
        saved = [(e, dict(e.attrib)) for e in self.svg.iter() if isinstance(e.tag, str)]
        centres = []
        for element in self.art_selection():
            box = element.bounding_box(element.getparent().composed_transform())
            if box is not None:
                centres.append((box.center_x, box.center_y))
        for e, attributes in saved:
            if dict(e.attrib) != attributes:
                e.attrib.clear()
                e.attrib.update(attributes)
        return centres

    def add_pin(self, layer, x: float, y: float, radius: float):
        """A pin marker at (x, y): a dot, and a tick that shows how it is turned."""
        n = len(self.pins()) + 1
        group = layer.add(inkex.Group())
        group.set_random_id("pin")
        group.label = f"Pin {n}"
        group.set(REST, f"{x!r} {y!r}")
        dot = group.add(inkex.Circle(cx=repr(x), cy=repr(y), r=repr(radius)))
        dot.style = {"fill": "#e8413c", "stroke": "#ffffff", "stroke-width": repr(radius * 0.3)}
        tick = group.add(inkex.Line(x1=repr(x), y1=repr(y), x2=repr(x), y2=repr(y - 2.5 * radius)))
        tick.style = {"stroke": "#e8413c", "stroke-width": repr(radius * 0.4), "stroke-linecap": "round"}

    # ---- the rest drawing kept in the document

    def store(self, create: bool):
        for store in self.svg.iter(STORE):
            return store
        if not create:
            return None
        return self.svg.metadata.add(etree.Element(STORE))

    def kept(self):
        """``{id: rest XML}`` of the elements (and definitions) kept at their rest."""
        store = self.store(create=False)
        return {} if store is None else {k.get("element"): k.text for k in store.iterfind(KEPT)}

    def keep(self, element):
        """Keeps `element`'s rest, once."""
        store = self.store(create=True)
        if element.get("id") in self.kept():
            return
        kept = etree.SubElement(store, KEPT)
        kept.set("element", element.get("id"))
        kept.text = etree.tostring(element, encoding="unicode")

    def restore_rest(self):
        """Puts every kept element back at its rest and removes what a warp added; returns the
        kept elements' ids."""
        for added in [e for e in self.svg.iter() if isinstance(e.tag, str) and e.attrib.get(ADDED)]:
            added.getparent().remove(added)
        ids = []
        for eid, text in self.kept().items():
            current = self.svg.getElementById(eid)
            rest = etree.fromstring(text, parser=inkex.SVG_PARSER)
            if current is not None:
                current.getparent().replace(current, rest)
            ids.append(eid)
        return ids

    def restore(self):
        if not self.kept():
            raise inkex.AbortExtension("Puppet Warp: nothing was warped in this document")
        self.restore_rest()
        store = self.store(create=False)
        metadata = store.getparent()
        metadata.remove(store)
        if len(metadata) == 0 and not (metadata.text or "").strip():
            metadata.getparent().remove(metadata)

    # ---- apply

    def art_selection(self):
        """The selected elements, less the pins and their layer."""
        layer = self.pins_layer(create=False)
        return [
            e for e in self.svg.selection.values()
            if layer is None or (e is not layer and layer not in e.iterancestors())
        ]

    def apply(self):
        splineskin = splineskin_module()
        pins = self.pins()
        if not pins:
            raise inkex.AbortExtension(
                "Puppet Warp: no pins in this document: add some first (Extensions › Puppet Warp › Add pin)"
            )
        selected = [e.get_id() for e in self.art_selection()]
        kept = self.restore_rest()
        # Warped before and selected now; not what the user has deleted since.
        warped = [e for e in dict.fromkeys(kept + selected) if self.svg.getElementById(e) is not None]
        if not warped:
            raise inkex.AbortExtension("Puppet Warp: select the art to warp")
        for eid in warped:
            self.keep(self.svg.getElementById(eid))
        handles = [rest for _, rest in pins]
        transforms = [self.pin_map(group) for group, _ in pins]
        deformed = self.deform(splineskin, warped, handles, transforms)
        self.put_back(deformed, warped)

    def pin_map(self, group):
        """The pin's affine map, ``[[a, c, e], [b, d, f]]``: its transform from rest (in the
        root's user units: the pins' layer's own transform included). Read from the attributes'
        text, as written: inkex's `transform` property (and its `get`) gives them rounded to six
        digits, and writes them back so."""
        m = inkex.Transform()
        for e in [group, *group.iterancestors()]:
            if e is self.svg:
                break
            m = inkex.Transform(e.attrib.get("transform")) @ m
        return [list(m.matrix[0]), list(m.matrix[1])]

    def warp_copy(self, warped: list[str]):
        """The document with only the warped elements, their groups and the definitions."""
        root = etree.fromstring(etree.tostring(self.svg), parser=inkex.SVG_PARSER)
        keep_ids = set(warped)

        def prune(parent):
            for child in list(parent):
                if not isinstance(child.tag, str):
                    continue
                if child.tag in KEPT_TAGS or child.get("id") in keep_ids:
                    continue
                if any(d.get("id") in keep_ids for d in child.iterdescendants()) and child.get(ROLE) != "pins":
                    prune(child)
                else:
                    parent.remove(child)

        prune(root)
        for store in list(root.iter(STORE)):
            store.getparent().remove(store)
        return etree.tostring(root, encoding="unicode")

    def deform(self, splineskin, warped, handles, transforms):
        """splineskin's deformation of the warped copy: the deformed document's root."""
        import numpy as np

        name = os.path.basename(self.svg.get(inkex.addNS("docname", "sodipodi")) or "drawing.svg")
        options = self.options
        kwargs = {"weights": options.weights}
        if options.weights == "shepard":
            kwargs["exponent"] = options.stiffness
        else:
            kwargs["margin"] = options.expansion / 100.0
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, name)
            with open(path, "w", encoding="utf-8") as f:
                f.write(self.warp_copy(warped))
            try:
                drawing = splineskin.Drawing.from_svg(path)
                rig = splineskin.SplineRig(drawing, np.array(handles, dtype=np.float64), **kwargs)
                text = rig.to_svg(np.array(transforms, dtype=np.float64))
            except (splineskin.SplineSkinError, ValueError) as e:
                raise inkex.AbortExtension(f"Puppet Warp: {e}")
        return etree.fromstring(text.encode("utf-8"), parser=inkex.SVG_PARSER)

    def put_back(self, deformed, warped):
        """The deformed elements in place of the document's, by id. Resources the warp changed
        (gradients, patterns, …) are replaced, their rest kept; those it added (a gradient's
        copy for one element) are put after the element they follow there, marked as added so
        that the next Apply or Restore removes them."""
        identified = [e for e in deformed.iter() if isinstance(e.tag, str) and e.get("id") and e is not deformed]
        added = [(e, self.anchor_of(e)) for e in identified if self.svg.getElementById(e.get("id")) is None]
        for eid in warped:
            current = self.svg.getElementById(eid)
            twin = deformed.find(f".//*[@id='{eid}']")
            if twin is not None and current is not None:
                current.getparent().replace(current, twin)
        for e in identified:
            current = self.svg.getElementById(e.get("id"))
            if current is not None and current is not e and e.tag in RESOURCE_TAGS \
                    and etree.tostring(current) != etree.tostring(e):
                self.keep(current)
                current.getparent().replace(current, e)
        for e, anchor in added:
            e.set(ADDED, "true")
            placed = self.svg.getElementById(anchor) if anchor is not None else None
            if placed is not None:
                placed.addnext(e)
            else:
                self.svg.defs.append(e)

    @staticmethod
    def anchor_of(e):
        """The id of the nearest sibling before `e` that has one (where `e` goes), or None."""
        anchor = e.getprevious()
        while anchor is not None and (not isinstance(anchor.tag, str) or anchor.get("id") is None):
            anchor = anchor.getprevious()
        return None if anchor is None else anchor.get("id")


if __name__ == "__main__":
    PuppetWarp().run()
