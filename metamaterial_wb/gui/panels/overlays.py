"""Temporary Coin overlays in the 3D view (axis lines, floor) drawn while a panel is open."""
import FreeCADGui


class _Overlay:
    """A Coin group added to a 3D view's scene graph; ``remove`` takes it out again."""
    view = None
    root = None

    def remove(self):
        if self.view is not None:
            try:
                self.view.getSceneGraph().removeChild(self.root)
            except Exception:  # pragma: no cover - view already gone
                pass
        self.view = None


class AxisOverlay(_Overlay):
    """Temporary Coin lines in the 3D view: candidate grid lines (grey) and chosen axes (orange)."""

    def __init__(self, doc):
        from pivy import coin
        self.coin = coin
        self.view = None
        gd = FreeCADGui.getDocument(doc.Name)
        if gd is not None and hasattr(gd.ActiveView, "getSceneGraph"):
            self.view = gd.ActiveView
        self.root = coin.SoSeparator()
        self.root.setName("MetamaterialAxes")
        if self.view is not None:
            self.view.getSceneGraph().addChild(self.root)

    def _group(self, segments, rgb, width, pattern):
        coin = self.coin
        sep = coin.SoSeparator()
        col = coin.SoBaseColor()
        col.rgb = rgb
        style = coin.SoDrawStyle()
        style.lineWidth = width
        style.linePattern = pattern
        pts = coin.SoCoordinate3()
        pts.point.setValues(0, len(segments) * 2, [p for seg in segments for p in seg])
        lines = coin.SoLineSet()
        lines.numVertices.setValues(0, len(segments), [2] * len(segments))
        for n in (col, style, pts, lines):
            sep.addChild(n)
        return sep

    def _label(self, text, at, rgb):
        coin = self.coin
        sep = coin.SoSeparator()
        col = coin.SoBaseColor()
        col.rgb = rgb
        tr = coin.SoTranslation()
        tr.translation.setValue(*at)
        txt = coin.SoText2()
        txt.string.setValue(text)
        for n in (col, tr, txt):
            sep.addChild(n)
        return sep

    def show(self, candidates, chosen, labels=()):
        """Grid lines (grey dashed), chosen axes (orange) and, at the start of each candidate line, its
        name ("col 3", "row 1": the numbers the panel's buttons and the messages use)."""
        self.root.removeAllChildren()
        self.n_candidates, self.n_chosen = len(candidates), len(chosen)
        if candidates:
            self.root.addChild(self._group(candidates, (0.55, 0.55, 0.6), 1.0, 0x0F0F))
        if chosen:
            self.root.addChild(self._group(chosen, (1.0, 0.5, 0.0), 4.0, 0xFFFF))
        self.labels = list(labels)
        for text, seg in zip(self.labels, candidates):
            self.root.addChild(self._label(text, seg[0], (0.1, 0.1, 0.1)))


class FloorOverlay(_Overlay):
    """Temporary translucent floor (Coin) under a simulated trajectory, tilted by its incline."""

    def __init__(self, doc, corners):
        from pivy import coin
        self.view = None
        self.root = coin.SoSeparator()
        self.root.setName("MetamaterialFloor")
        mat = coin.SoMaterial()
        mat.diffuseColor = (0.45, 0.38, 0.3)
        mat.transparency = 0.5
        pts = coin.SoCoordinate3()
        pts.point.setValues(0, 4, [tuple(float(v) for v in c) for c in corners])
        face = coin.SoFaceSet()
        face.numVertices.setValues(0, 1, [4])
        hints = coin.SoShapeHints()
        hints.vertexOrdering = coin.SoShapeHints.COUNTERCLOCKWISE
        for n in (hints, mat, pts, face):
            self.root.addChild(n)
        gd = FreeCADGui.getDocument(doc.Name)
        if gd is not None and hasattr(gd.ActiveView, "getSceneGraph"):
            self.view = gd.ActiveView
            self.view.getSceneGraph().addChild(self.root)


def axis_segment(scene, direction, line, z):
    """End points (flat sheet, mm) of an axis' grid line: across every joint it crosses, plus a margin.

    Node N(i,j) sits at (j p, -i p); a vertical axis on cell column k lies at x = (k + 1/2) p and crosses
    H(i,k) for the node rows i of its cells; a horizontal one on cell row k lies at y = -(k + 1/2) p.
    """
    p = scene.cell_size_mm
    m = 0.6
    if direction == "vertical":
        rows = [i for (i, j) in scene.cells if j == line]
        x = (line + 0.5) * p
        return ((x, -(min(rows) - m) * p, z), (x, -(max(rows) + 1 + m) * p, z))
    cols = [j for (i, j) in scene.cells if i == line]
    y = -(line + 0.5) * p
    return (((min(cols) - m) * p, y, z), ((max(cols) + 1 + m) * p, y, z))
