<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1">
<context>
    <name>Metamaterial</name>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="229"/>
        <source> (slider +-{0:.1f})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="177"/>
        <source> (the first {0:g} s of the {1:g} s timeline compared)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="123"/>
        <source> ({0} set directly for this joint: the sizes do not change it)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="317"/>
        <source>({0:.1f} s, {1} fits). OK applies it.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="134"/>
        <source>...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="457"/>
        <source>1 000 or {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="181"/>
        <source>1.00</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="38"/>
        <source>3MF (PLA nodes / TPU hinges)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="501"/>
        <source>; centre of mass moved {0:+.2f} mm</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="181"/>
        <source>; no speed down to {0:g}x follows it: slow the motion down</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="441"/>
        <source>; the box kept {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="186"/>
        <source>; {0:g}x follows it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="184"/>
        <source>; {0:g}x follows its first {1:g} s (Connect compares the whole timeline)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="69"/>
        <source>= {0} joint rotation</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="394"/>
        <source>? deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="102"/>
        <source>? deg ({0:+.3f})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="28"/>
        <source>All hinges</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="181"/>
        <source>Back to the motion profiles (quadratic model)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="54"/>
        <source>Build the sheet (and modules) and write the files in the background</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="45"/>
        <source>Cancel</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="96"/>
        <source>Cap diameter (core_diameter_mm)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="71"/>
        <source>Cell size</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="101"/>
        <source>Cell types (row = type index)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="76"/>
        <source>Chain</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="115"/>
        <source>Check on a 3-D frame: first peaks and sequence</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="77"/>
        <source>Clear</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="71"/>
        <source>Click a hinge in the 3D view</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="72"/>
        <source>Click a node in the 3D view</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="81"/>
        <source>Click cells [row, col] to add or remove them:</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/rotary_axes.py" line="24"/>
        <source>Click grid lines here, or click a hinge in the 3D view.
Vertical axes run down a cell column and cross its H joints;
horizontal axes run along a cell row and cross its V joints.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="69"/>
        <source>Columns</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="145"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="562"/>
        <source>Connect</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="108"/>
        <source>D {0:+.3f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="166"/>
        <source>Dask scheduler</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="554"/>
        <source>Disconnect</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="53"/>
        <source>Export</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="139"/>
        <source>Export STEP + 3MF</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="44"/>
        <source>Folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="155"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="300"/>
        <source>Forbidden joints</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="54"/>
        <source>Frequency</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="182"/>
        <source>Global deformation</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="32"/>
        <source>Global deformation (perfect propagation)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="75"/>
        <source>Grid</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="135"/>
        <source>Hold every fold within what the printed hinges fit in their node plates (otherwise the kinematic maximum applies and Export may refuse the design)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="70"/>
        <source>How far the joint turns for this value (plate B relative to plate A, the servo's sign): the angle a servo on it is sent; closing and opening differ. A servo with scale_deg in the scene is sent value x scale_deg instead.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="52"/>
        <source>Joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="39"/>
        <source>Joint (or click a hinge)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="156"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="298"/>
        <source>Keep the motors, fit their values only</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="163"/>
        <source>Keyframes</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="205"/>
        <source>Keyframes of {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="37"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="53"/>
        <source>Length</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="134"/>
        <source>Limit to printable folds</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="103"/>
        <source>Load scene file...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="170"/>
        <source>Load...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="121"/>
        <source>Loop</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="55"/>
        <source>Lowest .. highest angle sent to the servo over the profile's swing (closing and opening differ, the sign is the servo's)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="30"/>
        <source>Model</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="37"/>
        <source>Module</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="40"/>
        <source>Modules as separate files</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="180"/>
        <source>Motors</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="43"/>
        <source>Motors and constraints</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="67"/>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="38"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="68"/>
        <source>Name</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="62"/>
        <source>No motors yet: use 'Place motor'.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="133"/>
        <source>No rotary axes yet: use 'Rotary axes' first.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="38"/>
        <source>On (or click in the 3D view)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="44"/>
        <source>One joint (click a hinge in the 3D view)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="61"/>
        <source>Open...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="185"/>
        <source>Pause</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="55"/>
        <source>Phase offset</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="119"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="572"/>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="190"/>
        <source>Play</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="171"/>
        <source>Play DIR/trajectory.json written by 'python3 -m metamaterial_wb simulate SCENE --seconds S --out DIR'</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="149"/>
        <source>Port</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="125"/>
        <source>Predict</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="112"/>
        <source>Ring pattern</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="113"/>
        <source>Rings</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="68"/>
        <source>Rows</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="171"/>
        <source>Run</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="167"/>
        <source>Run build's geometry checks on the answer (a child process)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="179"/>
        <source>Run the dynamics model on this structure in the background, then play it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="36"/>
        <source>STEP (named bodies, assembly)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="152"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="299"/>
        <source>Servo budget</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="178"/>
        <source>Simulate</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="167"/>
        <source>Simulated trajectory (dynamics: gravity, floor contact, friction)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="53"/>
        <source>Sine amplitude</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="42"/>
        <source>Snap-fit sockets on the nodes</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="62"/>
        <source>Spec</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="46"/>
        <source>Stop this job; nothing it would have written is kept</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="164"/>
        <source>Stream the values shown to the servo firmware at 50 Hz (port loop:// = dry run without hardware)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="138"/>
        <source>Target file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="104"/>
        <source>The angle sent to the servo for this value (closing and opening differ); the firmware's invert and trim come after</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="93"/>
        <source>The structure comes from the scene file (its cells, cell size and motors): the grid and the cell size above are not used. Clear the file field to use them again.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="187"/>
        <source>The view follows the folds live; Confirm (OK) stores them with the joint configuration.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="39"/>
        <source>Thickness</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="126"/>
        <source>Unit-cell and sleeve force-displacement curves, snapping sequence (core.sleeve, about a second per curve)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="40"/>
        <source>Value D (-1..1)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="38"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="54"/>
        <source>Width</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="163"/>
        <source>Workers</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="345"/>
        <source>a keyframes profile is edited in its time / value table below</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="200"/>
        <source>achieved frame rate while playing and the real-time factor (animation seconds per wall second, over the speed): 1.00 = real time</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="207"/>
        <source>actuator.core_diameter_mm: the cap the inner membrane pushes on; at most the sleeve's inner diameter N (L + c) / pi - T</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="51"/>
        <source>amplitude</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="172"/>
        <source>at {0:g}x the link's {1:g} frames a second cannot follow the motion: {2}, moving straight from frame to frame, would be {3:.1f} deg off it at t = {4:.2f} s (at most {5:g} deg, as the stream command allows)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="88"/>
        <source>automatic</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="197"/>
        <source>automatic: the default cap, {0:g} mm</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="194"/>
        <source>automatic: the sleeve's inner diameter {0:.6g} mm (the default {1:g} mm does not fit)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="418"/>
        <source>building the sleeve ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="438"/>
        <source>cannot move the files into {0}: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="545"/>
        <source>cannot stream to {0}: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="154"/>
        <source>cell [{0}, {1}]</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="109"/>
        <source>cell type index of each cell around the circumference</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="50"/>
        <source>clip {0} ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="154"/>
        <source>e.g. H0,0, V1,2 (or click hinges)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="179"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="460"/>
        <source>export cancelled: nothing written</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="391"/>
        <source>export: an export is running (Cancel it first)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="397"/>
        <source>export: choose a folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="394"/>
        <source>export: the prediction is still running: wait or cancel it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="455"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="412"/>
        <source>export: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="60"/>
        <source>frame {0}: {1:.1f} ms (no recompute)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="52"/>
        <source>freq (Hz)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="120"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="95"/>
        <source>k1 = {0:.3f}, k2 = {1:.3f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="41"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="55"/>
        <source>k1, k2</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="223"/>
        <source>kinematic +-{0:.3f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="224"/>
        <source>kinematic: n/a</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="137"/>
        <source>length</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="162"/>
        <source>local worker processes for the candidate evaluations (inverse --workers)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="172"/>
        <source>max |D| = {0:.3f}; update {1:.1f} ms (solve {2:.1f}, preview {3:.1f}; no recompute, nothing written)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="116"/>
        <source>model.frame_nonlinear: the same beams as a nonlinear 3-D frame on the cylinder (core/sleeve/frame3d_nl.py), which bends the wall out of it as the printed sleeve does: each uniform ring's first peak (under a second per cell type) and the sleeve's snapping sequence and lean (about 10 s per ring; stacked rings with the plates between them free). Needs the curved single-layout ring</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="50"/>
        <source>motor</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="196"/>
        <source>motor values now: the angle sent to each servo (value in -1..1)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="49"/>
        <source>motor {0} ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="487"/>
        <source>not applied: the structure this panel edits was deleted (press Cancel)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="117"/>
        <source>not picked: {0} {1} ({2})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="193"/>
        <source>note: at {0:g}x the link's frames follow the first {1:g} s of the {2:g} s timeline; the rest is compared at Connect only (it takes seconds): Disconnect and Connect to compare all of it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="165"/>
        <source>optional: tcp://HOST:PORT of a Dask scheduler</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="102"/>
        <source>or a scene file (.json): type its path</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="146"/>
        <source>or target object</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="97"/>
        <source>out of the calibrated range</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="114"/>
        <source>overridden by Global deformation (untick it to use the motors)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="53"/>
        <source>phase (deg)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="563"/>
        <source>picked {0} {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="191"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="461"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="510"/>
        <source>playing: the motors' profiles</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="445"/>
        <source>playing: {0}, {1} frames, {2:.2f} s, incline {3:g} deg (side view mapped onto the x-z plane: one rigid body per column)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="347"/>
        <source>predict: the export is still running: wait or cancel it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="356"/>
        <source>predicting ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="378"/>
        <source>prediction cancelled</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="225"/>
        <source>printable +-{0:.3f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="226"/>
        <source>printable: n/a</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="447"/>
        <source>removed the earlier export's {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="312"/>
        <source>scene {0}: {1} cells, {2} motors</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="54"/>
        <source>servo angle range</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="50"/>
        <source>shape</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="490"/>
        <source>simulating {0:g} s ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="514"/>
        <source>simulation cancelled; playing: the motors' profiles</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="509"/>
        <source>simulation failed: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="504"/>
        <source>simulation warning: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="140"/>
        <source>sleeve.step (named bodies) and sleeve.3mf (TPU sleeve, PLA rings and caps, per-part extruders; sleeve_plate1.3mf, sleeve_plate2.3mf, ... when the parts need more than one bed, and an earlier export's plates this one does not write are removed), as 'sleeve SPEC --step --3mf'</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="135"/>
        <source>speed</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="564"/>
        <source>streamed {0} frames, {1} acknowledged</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="141"/>
        <source>t = 0.00 s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="48"/>
        <source>t = {0:.2f} s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="133"/>
        <source>target JSON, solve result, .stl / .obj / .step</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="89"/>
        <source>the default cap, {0:g} mm, or the sleeve's inner diameter N (L + c) / pi - T when that is smaller; untick to give your own (kept as typed, refused when it does not fit)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="156"/>
        <source>the hardware package (metamaterial_wb.hardware) is not available</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="445"/>
        <source>the structure this panel edits was deleted (press Cancel)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="179"/>
        <source>the {0} solve did not converge: the pose shown is its last iterate</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="295"/>
        <source>this spec has a per-ring pattern; it is kept as in the file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="166"/>
        <source>time (s)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="561"/>
        <source>under the cursor: {0} {1} (click to pick it)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="114"/>
        <source>under the cursor: {0} {1} (not a target: {2})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="167"/>
        <source>value (-1..1)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="108"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="315"/>
        <source>warning: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="445"/>
        <source>wrote {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="448"/>
        <source>wrote {0} file(s) to {1}: {2} ({3:.1f} s)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="395"/>
        <source>{0:+.1f} .. {1:+.1f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="103"/>
        <source>{0:+.1f} deg ({1:+.3f})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="150"/>
        <source>{0:+.3f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="175"/>
        <source>{0:.1f} frames/s achieved (target {1:.0f}); real-time factor {2:.2f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="336"/>
        <source>{0:.2f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/rotary_axes.py" line="28"/>
        <source>{0} axes ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="265"/>
        <source>{0} cells: a valid layout</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="264"/>
        <source>{0} cells: a valid layout (the full grid)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="105"/>
        <source>{0} goes across a joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="103"/>
        <source>{0} goes on a joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="106"/>
        <source>{0} goes on a node</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="469"/>
        <source>{0} has more decimals than the box takes (at most {1} decimals){2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="468"/>
        <source>{0} is not a whole number (at most 0 decimals){1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="461"/>
        <source>{0} is outside the allowed range {1}{2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="342"/>
        <source>{0} keeps its {1} profile as stored: these boxes do not apply to it. Choose another shape to replace it.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="422"/>
        <source>{0} this panel shows was deleted from the structure (press Cancel and open the panel again)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="471"/>
        <source>{0} was not taken as typed (allowed range {1}, at most {2} decimals){3}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="446"/>
        <source>{0} was not taken: the box reads only the ASCII digits 0-9, not {1}{2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="448"/>
        <source>{0} was not taken: the box reads only the digits 0-9 and {1}-{2}, not {3}{4}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="452"/>
        <source>{0} was not taken: the decimal point of this box is {1}, not {2}{3}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="458"/>
        <source>{0} was not taken: this box reads a space only between groups of three digits (a thousand is {1}){2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="227"/>
        <source>{0}, {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="329"/>
        <source>{0}: a key at {1:.3f} s lies beyond the period of {2:.3f} s: the period becomes {3:.3f} s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="325"/>
        <source>{0}: keyframes play once (stored without a period) and hold the last value</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="333"/>
        <source>{0}: keyframes repeat every {1:.3f} s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="122"/>
        <source>{0}; {1} is a {2}: click a {3} or choose one in the list (the target is still {4})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="159"/>
        <source>{0}{1} {2}</source>
        <translation type="unfinished"></translation>
    </message>
</context>
</TS>
