"""Fixtures and helpers shared by the GUI test modules (imported after their GuiUp guard)."""
import FreeCAD
import FreeCADGui
import pytest
from PySide import QtCore, QtGui

from metamaterial_wb.gui import panels


@pytest.fixture(scope="module", autouse=True)
def workbench():
    FreeCADGui.activateWorkbench("MetamaterialWorkbench")
    yield


@pytest.fixture
def tracebacks():
    """Exceptions raised in Qt slots (timer ticks, slider signals) reach sys.excepthook: collected here."""
    import sys
    import traceback
    seen = []
    old = sys.excepthook

    def hook(t, v, tb):
        seen.append("".join(traceback.format_exception(t, v, tb)))
    sys.excepthook = hook
    yield seen
    sys.excepthook = old


@pytest.fixture
def doc():
    """A fresh active document; any open task panel is rejected and the document closed afterwards."""
    d = FreeCAD.newDocument("MMGui")
    FreeCAD.setActiveDocument(d.Name)
    name = d.Name
    yield d
    if FreeCADGui.Control.activeDialog():
        if panels.active() is not None:
            panels.active().reject()
        else:
            FreeCADGui.Control.closeDialog()
    if name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(name)


def run_panel(cmd):
    """Run a workbench command and return the task panel it opened."""
    FreeCADGui.runCommand(cmd)
    QtGui.QApplication.processEvents()
    p = panels.active()
    assert p is not None and FreeCADGui.Control.activeDialog(), f"{cmd} opened no task panel"
    return p


# ---- real widget events (QTest): clicks, typing, slider drags, the task dialog's buttons, the 3D view
def qtest():
    try:
        from PySide2 import QtTest
    except ImportError:   # FreeCAD 1.1: PySide6
        from PySide6 import QtTest
    return QtTest.QTest


def process(ms=0):
    """Process events (for ``ms`` milliseconds)."""
    import time
    end = time.perf_counter() + ms / 1000.0
    QtGui.QApplication.processEvents()
    while time.perf_counter() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.005)


def click(widget):
    """A real left click in the middle of ``widget``."""
    from PySide import QtCore
    assert widget.isVisible(), f"{widget} is not visible"
    if isinstance(widget, (QtGui.QCheckBox, QtGui.QRadioButton)):     # on the box, not the empty stretch
        pos = QtCore.QPoint(8, widget.height() // 2)
        qtest().mouseClick(widget, QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier, pos)
    else:
        qtest().mouseClick(widget, QtCore.Qt.MouseButton.LeftButton)
    process()


def type_into(edit, text, enter=False):
    """Select everything in a line edit / spin box, type ``text`` and leave the field with Tab (as a
    user moving on; ``enter=True`` presses Return instead, which also triggers the dialog's OK)."""
    from PySide import QtCore
    edit.setFocus()
    line = edit.lineEdit() if hasattr(edit, "lineEdit") and edit.lineEdit() is not None else edit
    line.selectAll()
    qtest().keyClicks(line, text)
    qtest().keyClick(line, QtCore.Qt.Key.Key_Return if enter else QtCore.Qt.Key.Key_Tab)
    process()
    if edit.hasFocus() or line.hasFocus():       # the window had no keyboard focus: leave the field anyway
        line.clearFocus()
        edit.clearFocus()
        process()


def _slider_geometry(slider):
    opt = QtGui.QStyleOptionSlider()
    slider.initStyleOption(opt)
    opt.rect = slider.rect()
    opt.minimum, opt.maximum = slider.minimum(), slider.maximum()
    opt.sliderPosition = opt.sliderValue = slider.value()
    opt.orientation = slider.orientation()
    style = slider.style()
    handle = style.subControlRect(QtGui.QStyle.ComplexControl.CC_Slider, opt,
                                  QtGui.QStyle.SubControl.SC_SliderHandle, slider)
    groove = style.subControlRect(QtGui.QStyle.ComplexControl.CC_Slider, opt,
                                  QtGui.QStyle.SubControl.SC_SliderGroove, slider)
    return handle, groove


def _slider_x(slider, v):
    """The handle centre's x for value ``v`` with the slider's current geometry."""
    handle, groove = _slider_geometry(slider)
    span = groove.width() - handle.width()
    return groove.x() + handle.width() // 2 + QtGui.QStyle.sliderPositionFromValue(
        slider.minimum(), slider.maximum(), int(round(v)), span)


def drag_slider(slider, value, steps=8):
    """Drag the slider's handle with the mouse to where ``value`` is (press, moves, release). Each move
    is aimed with the slider's geometry of that moment (the panel may re-lay itself out while the view
    follows the drag)."""
    from PySide import QtCore
    process(100)                      # the panel's layout settles (the slider gets its width)
    handle, _groove = _slider_geometry(slider)
    y = handle.center().y()
    v0 = slider.value()
    t = qtest()
    t.mousePress(slider, QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier, handle.center())
    pos = handle.center()
    for k in range(1, steps + 1):
        pos = QtCore.QPoint(_slider_x(slider, v0 + (value - v0) * k / steps), y)
        ev = QtGui.QMouseEvent(QtCore.QEvent.Type.MouseMove, QtCore.QPointF(pos), QtCore.Qt.MouseButton.LeftButton,
                               QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier)
        QtGui.QApplication.sendEvent(slider, ev)
        process()
    t.mouseRelease(slider, QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier, pos)
    process()


def dialog_button(which="Ok"):
    from metamaterial_wb.gui.panels.base import task_buttons
    box = task_buttons()
    assert box is not None, "no task dialog is shown"
    return box.button(getattr(QtGui.QDialogButtonBox.StandardButton, which))


def press_ok():
    """Click the task dialog's OK button; True when the panel closed."""
    b = dialog_button("Ok")
    if b.isEnabled():
        click(b)
    else:
        process()
    return panels.active() is None


def press_cancel():
    click(dialog_button("Cancel"))
    return panels.active() is None


def view_widget():
    """The 3D view's GL viewport (receives the mouse events Coin sees)."""
    view = FreeCADGui.ActiveDocument.ActiveView
    gv = view.graphicsView()
    return gv.viewport()


def screen_point(vec, timeout=5.0, stable_s=0.3):
    """Qt widget coordinates of a global 3D point in the active view.

    Waits until the view has settled: the panel's layout may make the 3D view narrower, Coin's viewport
    follows a widget resize only at the next render (under Xvfb it lags), and FreeCAD 1.x animates
    ViewFit. The point is read again after a redraw until the reads agree for ``stable_s`` and Coin's
    viewport has the widget's size (in device pixels)."""
    import time
    from PySide import QtCore
    view = FreeCADGui.ActiveDocument.ActiveView
    w = view_widget()
    deadline = time.perf_counter() + timeout
    last, since = None, None
    # Coin renders in device pixels: widget size x the device pixel ratio (Qt's high-DPI scaling; under
    # Xvfb at 100 dpi FreeCAD 0.20 gets 100 / 96)
    dpr = float(w.devicePixelRatioF()) if hasattr(w, "devicePixelRatioF") else 1.0
    while True:
        view.redraw()
        w.repaint()                  # a synchronous paint: Coin takes the widget's size at a render
        process(50)
        wc, hc = view.getSize()
        x, y = view.getPointOnScreen(vec)
        # Quarter maps widget pixels onto Coin's viewport: coin = (qx * Wc / Wq, Hc - 1 - qy * Hc / Hq)
        now = (wc, hc, w.width(), w.height(), int(round(x * w.width() / wc)),
               int(round((hc - 1 - y) * w.height() / hc)))
        settled = abs(wc - w.width() * dpr) <= 1 and abs(hc - w.height() * dpr) <= 1
        t = time.perf_counter()
        if now != last or not settled:
            since = t
        elif t - since >= stable_s:      # the same read for stable_s: a late layout change is seen
            break
        if t > deadline:
            raise AssertionError(f"the 3D view did not settle in {timeout} s: last reads {last} and {now} "
                                 "(Coin viewport w, h, widget w, h, point x, y)")
        last = now
    return QtCore.QPoint(now[4], now[5])


def hover_view(point):
    from PySide import QtCore
    w = view_widget()
    ev = QtGui.QMouseEvent(QtCore.QEvent.Type.MouseMove, QtCore.QPointF(point), QtCore.Qt.MouseButton.NoButton,
                           QtCore.Qt.MouseButton.NoButton, QtCore.Qt.KeyboardModifier.NoModifier)
    QtGui.QApplication.sendEvent(w, ev)
    process()


def click_view(point):
    from PySide import QtCore
    hover_view(point)
    qtest().mouseClick(view_widget(), QtCore.Qt.MouseButton.LeftButton, QtCore.Qt.KeyboardModifier.NoModifier, point)
    process()


def run_command(cmd):
    """Run a command as the toolbar would and return the task panel it opened."""
    return run_panel(cmd)


def shown_placements(arr):
    """The placements the 3D view shows for a link array: the open panel's live preview (a Coin overlay
    that writes no document property) when it draws this array, else the array's ``PlacementList``."""
    prev = getattr(panels.active(), "live_preview", None)
    if prev is not None and prev.active and arr in (prev.obj.NodeArray, prev.obj.HingeArray):
        pl = prev.placements("nodes" if arr == prev.obj.NodeArray else "hinges")
        if pl is not None:
            return pl
    return list(arr.PlacementList)


def hinge_mid(sc, joint):
    """Midpoint (document coordinates) of the hinge of ``joint``, through the structure's parents."""
    from metamaterial_wb.objects import structure
    from metamaterial_wb.core.live import joint_node_indices
    scene = structure.compose_scene(sc)
    a, b = joint_node_indices(scene, joint)
    g, parent = sc.NodeArray.Placement, sc.NodeArray.getParentGeoFeatureGroup()
    while parent is not None:
        g, parent = parent.Placement.multiply(g), parent.getParentGeoFeatureGroup()
    shown = shown_placements(sc.NodeArray)
    pa, pb = (g.multVec(shown[k].Base) for k in (a, b))
    return FreeCAD.Vector((pa.x + pb.x) / 2, (pa.y + pb.y) / 2, (pa.z + pb.z) / 2)


# ---- a narrow task dock (the combo view at its usual width) ----------------------------------------------------
def dock_of(widget):
    """The QDockWidget holding ``widget`` (None when it is in none)."""
    w = widget
    while w is not None and not isinstance(w, QtGui.QDockWidget):
        w = w.parentWidget()
    return w


def scroll_of(widget):
    """The innermost QScrollArea above ``widget`` (the task view's, for a panel's form)."""
    w = widget.parentWidget()
    while w is not None and not isinstance(w, QtGui.QScrollArea):
        w = w.parentWidget()
    return w


def overlay_of(dock):
    """FreeCAD 1.1's overlay panel holding ``dock`` over the 3D view, else None."""
    w = dock.parentWidget()
    while w is not None and not w.isWindow():
        if w.objectName().startswith("Overlay") and isinstance(w, QtGui.QTabWidget):
            return w
        w = w.parentWidget()
    return None


def narrowing(width, slack=40, require=True):
    """The body of a ``narrow`` fixture (``yield from narrowing(320)``): yields ``apply(panel, width=None)``, which
    asks for a task dock (the combo view / task view dock holding the panel) ``width`` px wide and returns the dock;
    with ``require`` it asserts the dock got within ``slack`` px (a panel wider than that makes it grow). The main
    window's state, size and overlays are put back after the test."""
    mw = FreeCADGui.getMainWindow()
    state = mw.saveState()
    size = mw.size()
    overlays = []                                # (overlay panel, its geometry before)
    if mw.width() < 1200:
        mw.resize(1280, max(mw.height(), 900))
    default = width

    def apply(p, width=None):
        width = default if width is None else width
        process(50)
        dock = dock_of(p.form)
        assert dock is not None, "the panel is not in a dock"
        overlay = overlay_of(dock)
        if overlay is not None:
            overlays.append((overlay, overlay.geometry()))
        for _attempt in range(20):               # FreeCAD may re-lay its docks out once more after a panel opens
            if overlay is not None:              # FreeCAD 1.1: the task view sits in an overlay panel over the 3D view
                g = overlay.geometry()
                w = width + overlay.width() - dock.width()
                overlay.setGeometry(g.x() + g.width() - w, g.y(), w, g.height())
            elif dock.isFloating():
                dock.resize(width, max(dock.height(), 800))
            else:
                area = mw.dockWidgetArea(dock)   # the docks sharing its column (the model view above it) too
                same = [d for d in mw.findChildren(QtGui.QDockWidget)
                        if d.isVisible() and not d.isFloating() and mw.dockWidgetArea(d) == area]
                mw.resizeDocks(same, [width] * len(same), QtCore.Qt.Orientation.Horizontal)
            process(100)
            if abs(dock.width() - width) <= slack:
                process(100)
                if abs(dock.width() - width) <= slack:
                    break
        if require:
            assert abs(dock.width() - width) <= slack, (dock.objectName(), dock.width(),
                                                         dock.minimumSizeHint().width(), overlay is not None)
        process(100)
        return dock
    yield apply
    for overlay, g in reversed(overlays):
        overlay.setGeometry(g)
    mw.restoreState(state)
    mw.resize(size)
    process()


def tab_chain(start, n):
    """Give ``start`` the focus and press Tab ``n`` times on whatever has it: ``[the widget with the focus first,
    then after each Tab]`` (n + 1 widgets)."""
    app = QtGui.QApplication.instance()
    start.setFocus()
    process()
    w = app.focusWidget()
    chain = [w]
    for _ in range(n):
        qtest().keyClick(w, QtCore.Qt.Key.Key_Tab)
        process()
        w = app.focusWidget()
        chain.append(w)
    return chain
