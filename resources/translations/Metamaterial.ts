<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1">
<context>
    <name>Metamaterial</name>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="233"/>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="212"/>
        <source> (the first {0:g} s of the {1:g} s timeline compared)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="124"/>
        <source> ({0} set directly for this joint: the sizes do not change it)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="98"/>
        <source>(click a hinge or choose)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="99"/>
        <source>(click a node or choose)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="147"/>
        <source>(use the file)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="451"/>
        <source>({0:.1f} s, {1} fits). OK applies it.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="139"/>
        <source>...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="592"/>
        <source>1 000 or {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="135"/>
        <source>1.00</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="38"/>
        <source>3MF (PLA nodes / TPU hinges)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="237"/>
        <source>; no speed down to {0:g}x follows it: slow the motion down</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="573"/>
        <source>; the box kept {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="242"/>
        <source>; {0:g}x follows it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="240"/>
        <source>; {0:g}x follows its first {1:g} s (Connect compares the whole timeline)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="73"/>
        <source>= {0} joint rotation</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="363"/>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="70"/>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="104"/>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="109"/>
        <source>? deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="129"/>
        <source>? deg ({0:+.3f})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="218"/>
        <source>Add key</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="139"/>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="25"/>
        <source>Add module</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="125"/>
        <source>Add type</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="28"/>
        <source>All hinges</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="136"/>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="17"/>
        <source>Angular constraint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="32"/>
        <source>Angular-constraint clip (joint)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="146"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="39"/>
        <source>Animate</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/preferences.py" line="12"/>
        <source>Animation frame rate (1/s)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="125"/>
        <source>Back to the motion profiles (quadratic model)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="55"/>
        <source>Build the sheet (and modules) and write the files in the background</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="45"/>
        <source>Cancel</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="116"/>
        <source>Cap diameter (core_diameter_mm)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="71"/>
        <source>Cell size</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="123"/>
        <source>Cell types (row = type index)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="76"/>
        <source>Chain</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="141"/>
        <source>Check on a 3-D frame: first peaks and sequence</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="77"/>
        <source>Clear</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="530"/>
        <source>Click a hinge in the 3D view</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="531"/>
        <source>Click a node in the 3D view</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="81"/>
        <source>Click cells [row, col] to add or remove them:</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/rotary_axes.py" line="27"/>
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
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="85"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="402"/>
        <source>Connect</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="29"/>
        <source>Connection hub (node)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="135"/>
        <source>D {0:+.3f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="181"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="432"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="366"/>
        <source>Dask scheduler</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="323"/>
        <source>Dask scheduler {0} (a values-only fit runs in this process)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="35"/>
        <source>Default servo</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="155"/>
        <source>Design a metamaterial sleeve actuator (curved-beam cells around a cylinder) from a spec file or parameters, build it, predict its force-displacement peaks and snapping sequence</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="394"/>
        <source>Disconnect</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/preferences.py" line="56"/>
        <source>Edit &gt; Preferences &gt; Metamaterial &gt; {0} ({1}): {2} is outside the allowed range {3}..{4}; set it there</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="80"/>
        <source>Edit &gt; Preferences &gt; Metamaterial &gt; {0}: {1} is not a known material; allowed: {2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="78"/>
        <source>Edit &gt; Preferences &gt; Metamaterial &gt; {0}: {1} is not a known servo; allowed: {2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="53"/>
        <source>Edit &gt; Preferences &gt; Metamaterial &gt; {0}: {1} mm is not below the {2} mm socket lip, so the modules' snap pins have nothing to latch on; allowed range [0, {2}) mm</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="25"/>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="54"/>
        <source>Export</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="166"/>
        <source>Export STEP + 3MF</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="150"/>
        <source>Export STEP / 3MF</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="159"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="124"/>
        <source>Fit to target</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="130"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="20"/>
        <source>Flexibility</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="33"/>
        <source>Flexible material (hinges)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="113"/>
        <source>Fold of {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="127"/>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="72"/>
        <source>Folded shape</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="44"/>
        <source>Folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="162"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="431"/>
        <source>Forbidden joints</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="317"/>
        <source>Forbidden joints {0} (the placement is the structure's)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="58"/>
        <source>Frequency</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="31"/>
        <source>Friction pad (node)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="90"/>
        <source>G (shear modulus)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="131"/>
        <source>Global and per-joint hinge sizes, with the resulting k1 / k2</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="136"/>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="46"/>
        <source>Global deformation</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="143"/>
        <source>Global-deformation slider and one slider per motor and constraint, solved live</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="75"/>
        <source>Grid</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="137"/>
        <source>Hold a joint at a fixed deformation (clip); shown as a blue disc</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="86"/>
        <source>Hold every fold within what the printed hinges fit in their node plates (otherwise the kinematic maximum applies and Export may refuse the design)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/rotary_axes.py" line="34"/>
        <source>Horizontal axes (rows)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="74"/>
        <source>How far the joint turns for this value (plate B relative to plate A, the servo's sign): the angle a servo on it is sent; closing and opening differ. A servo with scale_deg in the scene is sent value x scale_deg instead.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="160"/>
        <source>Inverse design: place N servos and find their values so the structure best reaches a target shape (file or document object); runs in the background</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="52"/>
        <source>Joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="42"/>
        <source>Joint (or click a hinge)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="239"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="163"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="429"/>
        <source>Keep the motors, fit their values only</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="209"/>
        <source>Keyframes</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="253"/>
        <source>Keyframes of {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="86"/>
        <source>L (beam span)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="118"/>
        <source>Lay out a new metamaterial sheet: toggle cells on a grid, chain / grid presets, or load a scene file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="37"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="53"/>
        <source>Length</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="85"/>
        <source>Limit to printable folds</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="103"/>
        <source>Load scene file...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="114"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="225"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="237"/>
        <source>Load...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="58"/>
        <source>Loop</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="193"/>
        <source>Loop: where the {0:g} s timeline wraps from its end back to its start the servos are sent a jump no servo follows: {1} (at most {2:g} deg, the stream command's rate tolerance); untick Loop, or set a length at which the motion ends where it starts</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="62"/>
        <source>Lowest .. highest angle sent to the servo over the profile's swing (closing and opening differ, the sign is the servo's)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="294"/>
        <source>Metamaterial</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="44"/>
        <source>Model</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="58"/>
        <source>Module</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="34"/>
        <source>Module material</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="40"/>
        <source>Modules as separate files</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="124"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="288"/>
        <source>Motors</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="63"/>
        <source>Motors and constraints</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="67"/>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="41"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="84"/>
        <source>Name</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="36"/>
        <source>New metamaterial structure</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="117"/>
        <source>New structure</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="86"/>
        <source>No motors yet: use 'Place motor'.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="84"/>
        <source>No rotary axes yet: use 'Rotary axes' first.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="59"/>
        <source>On (or click in the 3D view)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="160"/>
        <source>On: no hinge chosen yet; click one in the 3D view or choose it in the list</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="162"/>
        <source>On: no node chosen yet; click one in the 3D view or choose it in the list</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="44"/>
        <source>One joint (click a hinge in the 3D view)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="128"/>
        <source>One slider per axis (with its maximum); Confirm runs the joint configuration</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="121"/>
        <location filename="../../metamaterial_wb/gui/panels/open_example.py" line="33"/>
        <source>Open example</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="122"/>
        <source>Open one of the bundled examples (fish, worm, ...)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="74"/>
        <source>Open...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="201"/>
        <source>Pause</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="49"/>
        <source>Perfect propagation: every joint follows the global deformation; the motors' sliders are off while it is ticked</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="59"/>
        <source>Phase offset</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="125"/>
        <source>Pick the grid lines the structure folds about; rule violations are listed</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="133"/>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="16"/>
        <source>Place motor</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="56"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="412"/>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="206"/>
        <source>Play</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="115"/>
        <source>Play DIR/trajectory.json written by 'python3 -m metamaterial_wb simulate SCENE --seconds S --out DIR'</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="147"/>
        <source>Play the motors' motion profiles (sine amplitude, frequency, phase); stream to hardware</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="89"/>
        <source>Port</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="152"/>
        <source>Predict</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="134"/>
        <source>Put a servo on a joint (click a hinge); shown as a red sphere</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="219"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="126"/>
        <source>Remove last</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="32"/>
        <source>Rigid material (nodes)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="137"/>
        <source>Ring pattern</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="138"/>
        <source>Rings</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="124"/>
        <location filename="../../metamaterial_wb/gui/panels/rotary_axes.py" line="17"/>
        <source>Rotary axes</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="68"/>
        <source>Rows</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="195"/>
        <source>Run</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="182"/>
        <source>Run build's geometry checks on the answer (a child process)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="123"/>
        <source>Run the dynamics model on this structure in the background, then play it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="36"/>
        <source>STEP (named bodies, assembly)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="289"/>
        <source>Scene file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="291"/>
        <source>Scenes (*.json)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="159"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="430"/>
        <source>Servo budget</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="314"/>
        <source>Servo budget {0} (the fit keeps the structure's {1} motors)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="165"/>
        <source>Servo budget, Forbidden joints, Workers and Dask scheduler are not used: the fit keeps the structure's {0} motors on their joints and runs in this process (untick to use them again)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="28"/>
        <source>Servo housing (across a joint)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="140"/>
        <source>Servo housing, connection hubs, friction pad or clip on a node or joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="56"/>
        <source>Set for this joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="142"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="122"/>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="17"/>
        <source>Simulate</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="107"/>
        <source>Simulated trajectory</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="57"/>
        <source>Sine amplitude</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="154"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="60"/>
        <source>Sleeve actuator</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="286"/>
        <source>Sleeve spec</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="287"/>
        <source>Sleeve spec (*.json)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/checks.py" line="31"/>
        <source>Snap-fit clearance (mm)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="42"/>
        <source>Snap-fit sockets on the nodes</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="75"/>
        <source>Spec</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="30"/>
        <source>Stable connection hub (across a joint)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="46"/>
        <source>Stop this job; nothing it would have written is kept</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="104"/>
        <source>Stream the values shown to the servo firmware at 50 Hz (port loop:// = dry run without hardware)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="89"/>
        <source>T (wall thickness)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="215"/>
        <source>Target</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="143"/>
        <source>Target file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="216"/>
        <source>Targets (*.json *.stl *.obj *.step *.stp)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="131"/>
        <source>The angle sent to the servo for this value (closing and opening differ); the firmware's invert and trim come after</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="93"/>
        <source>The structure comes from the scene file (its cells, cell size and motors): the grid and the cell size above are not used. Clear the file field to use them again.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="141"/>
        <source>The view follows the folds live; Confirm (OK) stores them with the joint configuration.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="39"/>
        <source>Thickness</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="227"/>
        <source>Trajectory</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="228"/>
        <source>Trajectory (*.json)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="153"/>
        <source>Unit-cell and sleeve force-displacement curves, snapping sequence (core.sleeve, about a second per curve)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="48"/>
        <source>Use global deformation</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="57"/>
        <source>Use global size</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/place_item.py" line="43"/>
        <source>Value D (-1..1)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/rotary_axes.py" line="33"/>
        <source>Vertical axes (columns)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="38"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="54"/>
        <source>Width</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="178"/>
        <source>Workers</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="320"/>
        <source>Workers {0} (a values-only fit runs in this process)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="151"/>
        <source>Write STEP (named bodies) and 3MF (per-part materials) for dual-extruder printers</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="35"/>
        <source>a connection hub</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="342"/>
        <source>a fit is already running</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="37"/>
        <source>a friction pad</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="267"/>
        <source>a keyframes profile is edited in its time / value table below</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="34"/>
        <source>a servo housing</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="311"/>
        <source>a simulation is already running</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="36"/>
        <source>a stable connection hub</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="84"/>
        <source>a {0} wave needs a frequency &gt; 0 Hz (its period is 1 / f); got {1:g} Hz, allowed (0, {2:g}] Hz</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="53"/>
        <source>accuracy: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="147"/>
        <source>achieved frame rate while playing and the real-time factor (timeline seconds played per wall second): 1.00 = real time, 2.00 at speed 2</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="279"/>
        <source>actuator.core_diameter_mm: the cap the inner membrane pushes on, in the opening of the end ring; at most the sleeve's inner diameter N (L + c) / pi - T less two {0:g} mm ring walls</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="60"/>
        <source>amplitude</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="38"/>
        <source>an angular-constraint clip</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="80"/>
        <source>another task dialog is open</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="44"/>
        <source>asymmetric</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="228"/>
        <source>at {0:g}x the link's {1:g} frames a second cannot follow the motion: {2}, moving straight from frame to frame, would be {3:.1f} deg off it at t = {4:.2f} s (at most {5:g} deg, as the stream command allows)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="210"/>
        <source>at {0:g}x: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="107"/>
        <source>automatic</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="269"/>
        <source>automatic: the default cap, {0:g} mm</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="265"/>
        <source>automatic: {0:.6g} mm, the widest cap the end rings ({1:g} mm walls) hold inside the sleeve's inner diameter (the default {2:g} mm does not fit)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="161"/>
        <source>building the sheet ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="515"/>
        <source>building the sleeve ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="87"/>
        <source>c (pillar width)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="184"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="535"/>
        <source>cannot move the files into {0}: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="295"/>
        <source>cannot start {0}: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="385"/>
        <source>cannot stream to {0}: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="154"/>
        <source>cell [{0}, {1}]</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="134"/>
        <source>cell type index of each cell around the circumference</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="33"/>
        <source>cell type {0}: peak {1}, valley {2} (F / G L^2)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="31"/>
        <source>cell type {0}: peak {1}, valley {2} (F / G L^2); {3}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="54"/>
        <source>channel map: {0}; each motor's angle is its own joint's</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="77"/>
        <source>choose STEP, 3MF or both</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="244"/>
        <source>choose a node or joint for the module</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/open_example.py" line="69"/>
        <source>choose an example</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="70"/>
        <source>clip {0} ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="88"/>
        <source>delta (gap)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="109"/>
        <source>dynamics: gravity, floor contact, friction</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="161"/>
        <source>e.g. H0,0, V1,2 (or click hinges)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="216"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="557"/>
        <source>export cancelled: nothing written</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="488"/>
        <source>export: an export is running (Cancel it first)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="494"/>
        <source>export: choose a folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/exporting.py" line="32"/>
        <source>export: give an output folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="491"/>
        <source>export: the prediction is still running: wait or cancel it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="552"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="509"/>
        <source>export: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/exporting.py" line="34"/>
        <source>export: {0} exists and is not a folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="439"/>
        <source>fit cancelled: nothing changed</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="424"/>
        <source>fit: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="63"/>
        <source>frame {0}: {1:.1f} ms (no recompute)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="60"/>
        <source>freq (Hz)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="335"/>
        <source>give a target file or pick a target object</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="81"/>
        <source>give an output folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="119"/>
        <source>h (mm)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="111"/>
        <source>horizontal {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="168"/>
        <source>joint {0} already carries the module {1}: one module per joint; choose another joint or delete {1} first</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="185"/>
        <source>joint {0} has no angular constraint for the clip to hold: place one on {0} first (Angular constraint), then add the clip</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="121"/>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="96"/>
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
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="29"/>
        <source>keyframes</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="177"/>
        <source>kinematic +-{0:.3f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="108"/>
        <source>kinematic maximum bound by {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="178"/>
        <source>kinematic: n/a</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="74"/>
        <source>length</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="19"/>
        <source>linear</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="177"/>
        <source>local worker processes for the candidate evaluations (inverse --workers)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="199"/>
        <source>max |D| = {0:.3f}; update {1:.1f} ms (solve {2:.1f}, preview {3:.1f}; no recompute, nothing written)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="142"/>
        <source>model.frame_nonlinear: the same beams as a nonlinear 3-D frame on the cylinder (core/sleeve/frame3d_nl.py), which bends the wall out of it as the printed sleeve does: each uniform ring's first peak (under a second per cell type) and the sleeve's snapping sequence and lean (about 10 s per ring; stacked rings with the plates between them free). Needs the curved single-layout ring</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/exporting.py" line="68"/>
        <source>modules cannot be built ({0}); nothing written - fix them or export without modules</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="59"/>
        <source>motor</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="142"/>
        <source>motor values now: the angle sent to each servo (value in -1..1)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="83"/>
        <source>motor {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="69"/>
        <source>motor {0} ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/open_example.py" line="62"/>
        <source>no example called {0}; have {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="48"/>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="105"/>
        <source>no servo mapping (metamaterial_wb.hardware: {0})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="171"/>
        <source>node {0} already carries the module {1}: one module per node socket; choose another node or delete {1} first</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="216"/>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="30"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="27"/>
        <source>none</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="288"/>
        <source>none: the structure's placement</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="290"/>
        <source>none: this process</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="21"/>
        <source>nonlinear</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="503"/>
        <source>not applied: the structure this panel edits was deleted (press Cancel)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="496"/>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="501"/>
        <source>not applied: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="156"/>
        <source>not exported: cannot write in {0}: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="134"/>
        <source>not exported: the structure this panel exports was deleted (press Cancel)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="209"/>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="129"/>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="140"/>
        <source>not exported: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="204"/>
        <source>not picked: hinge {0} ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="207"/>
        <source>not picked: node {0} ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="265"/>
        <source>not used while '{0}' is ticked: a values-only fit runs in this process (only the placement search runs in parallel)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="267"/>
        <source>not used while '{0}' is ticked: the fit keeps the structure's {1} motors</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="269"/>
        <source>not used while '{0}' is ticked: the placement is the structure's</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="295"/>
        <source>not used while a Dask scheduler is given: its workers run the search (clear the Dask scheduler to use local workers)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="301"/>
        <source>not used while a target object is picked: pick '{0}' to use the file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="249"/>
        <source>note: at {0:g}x the link's frames follow the first {1:g} s of the {2:g} s timeline; the rest is compared at Connect only (it takes seconds): Disconnect and Connect to compare all of it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="41"/>
        <source>nothing snapped</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="180"/>
        <source>optional: tcp://HOST:PORT of a Dask scheduler</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="102"/>
        <source>or a scene file (.json): type its path</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="153"/>
        <source>or target object</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="98"/>
        <source>out of the calibrated range</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="141"/>
        <source>overridden by Global deformation (untick it to use the motors)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="61"/>
        <source>phase (deg)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="583"/>
        <source>picked hinge {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="586"/>
        <source>picked node {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="136"/>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="278"/>
        <source>playing: the motors' profiles</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="268"/>
        <source>playing: {0}, {1} frames, {2:.2f} s, incline {3:g} deg (side view mapped onto the x-z plane: one rigid body per column)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="437"/>
        <source>predict: the export is still running: wait or cancel it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="449"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="458"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="238"/>
        <source>predicting ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="236"/>
        <source>predicting the values from when Predict was pressed (edited since) ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="451"/>
        <source>predicting: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="475"/>
        <source>prediction cancelled</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="470"/>
        <source>prediction failed: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="251"/>
        <source>prediction for the earlier values (edited since; press Predict for the values shown):</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="51"/>
        <source>pressure peaks {0} kPa</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="179"/>
        <source>printable +-{0:.3f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="180"/>
        <source>printable: n/a</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="20"/>
        <source>quadratic</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="90"/>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="68"/>
        <source>recompute failed</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="544"/>
        <source>removed the earlier export's {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="194"/>
        <source>removed {0} file(s) of the earlier export that this one does not write: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="400"/>
        <source>ring pattern {0}: expected cell type indices separated by commas, e.g. 0, 0, 1, 1</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="497"/>
        <source>run the fit first</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="309"/>
        <source>scene file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="322"/>
        <source>scene {0}: {1} cells, {2} motors</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="45"/>
        <source>sequence: loading {0}, unloading {1} -&gt; {2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="48"/>
        <source>sequence: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="61"/>
        <source>servo angle range</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="59"/>
        <source>shape</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="241"/>
        <source>simulated here</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="111"/>
        <source>simulated rotation of joint {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="326"/>
        <source>simulating {0:g} s ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="330"/>
        <source>simulating {0:g} s of dynamics ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="354"/>
        <source>simulation cancelled; {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="348"/>
        <source>simulation failed: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="341"/>
        <source>simulation warning: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="26"/>
        <source>sine</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="37"/>
        <source>sleeve ({0} x {1} cells): peaks {2}; valleys {3}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="167"/>
        <source>sleeve.step (named bodies) and sleeve.3mf (TPU sleeve, PLA rings and caps, per-part extruders; sleeve_plate1.3mf, sleeve_plate2.3mf, ... when the parts need more than one bed, and an earlier export's plates this one does not write are removed), as 'sleeve SPEC --step --3mf'</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="71"/>
        <source>speed</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="27"/>
        <source>square</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="377"/>
        <source>starting the fit</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="32"/>
        <source>stored constant</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="31"/>
        <source>stored steps</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="40"/>
        <source>stored {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="404"/>
        <source>streamed {0} frames, {1} acknowledged</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="57"/>
        <source>streaming stopped: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="43"/>
        <source>symmetric</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="119"/>
        <source>t (mm)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="81"/>
        <source>t = 0.00 s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="50"/>
        <source>t = {0:.2f} s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="138"/>
        <source>target JSON, solve result, .stl / .obj / .step</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="117"/>
        <source>target object {0}: it has no faces</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="114"/>
        <source>target object {0}: neither a mesh nor a shape</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/rotary_axes.py" line="108"/>
        <source>the axes break the rules: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="108"/>
        <source>the default cap, {0:g} mm, or the widest cap the end rings hold, the sleeve's inner diameter N (L + c) / pi - T less two {1:g} mm ring walls, when that is smaller; untick to give your own (kept as typed, refused when it does not fit)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/docwatch.py" line="308"/>
        <source>the document changed under this panel (Undo / Redo): the values shown are not the stored ones any more; press Cancel and open the panel again to edit the current state (or Undo / Redo back)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="286"/>
        <source>the export process ended with status {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="495"/>
        <source>the fit is still running: wait or cancel it</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="96"/>
        <source>the hardware package (metamaterial_wb.hardware) is not available</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="461"/>
        <source>the structure this panel edits was deleted (press Cancel)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="104"/>
        <source>the structure's {0} module(s) plug into the node sockets, but its fabrication.sockets is false: untick '{1}' to export the sheet alone, or set fabrication.sockets to true in the structure</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="108"/>
        <source>the structure's {0} module(s) plug into the node sockets: tick '{1}', or untick '{2}' to export the sheet alone</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="206"/>
        <source>the {0} solve did not converge: the pose shown is its last iterate</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="191"/>
        <source>this module</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="384"/>
        <source>this spec has a per-ring pattern; it is kept as in the file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="213"/>
        <source>time (s)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="249"/>
        <source>trajectory {0}: cannot read it ({1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="28"/>
        <source>triangle</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="302"/>
        <source>type the path of a scene file</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="582"/>
        <source>under the cursor: hinge {0} (click to pick it)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="203"/>
        <source>under the cursor: hinge {0} (not a target: {1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="585"/>
        <source>under the cursor: node {0} (click to pick it)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="206"/>
        <source>under the cursor: node {0} (not a target: {1})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="42"/>
        <source>undetermined</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/profiles.py" line="214"/>
        <source>value (-1..1)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="110"/>
        <source>vertical {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="117"/>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="196"/>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="449"/>
        <source>warning: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/flexibility.py" line="211"/>
        <source>with these sizes: {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="139"/>
        <location filename="../../metamaterial_wb/gui/panels/jobs.py" line="241"/>
        <source>working ...</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="542"/>
        <source>wrote {0}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="190"/>
        <source>wrote {0} file(s) to {1} in {2:.1f} s:</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="545"/>
        <source>wrote {0} file(s) to {1}: {2} ({3:.1f} s)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="364"/>
        <source>{0:+.1f} .. {1:+.1f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="110"/>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="70"/>
        <source>{0:+.1f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="130"/>
        <source>{0:+.1f} deg ({1:+.3f})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/simulate.py" line="177"/>
        <source>{0:+.3f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="191"/>
        <source>{0:.1f} frames/s achieved (target {1:.0f}); real-time factor {2:.2f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="284"/>
        <source>{0:.2f}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="198"/>
        <source>{0:g} deg is beyond the kinematic maximum of this axis: allowed range [-{1}, {1}] deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="195"/>
        <source>{0:g} deg is beyond the printable maximum of this axis: allowed range [-{1}, {1}] deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="191"/>
        <source>{0} (channel {1}) by {2:.2f} deg, from {3:+.2f} deg to {4:+.2f} deg</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="183"/>
        <source>{0} (slider +-{1:.1f})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="273"/>
        <source>{0} cells: a valid layout</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="272"/>
        <source>{0} cells: a valid layout (the full grid)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/docwatch.py" line="312"/>
        <source>{0} changed under this panel (another command or a script): OK would write the older value shown here over it; press Cancel and open the panel again to edit the current state (or change it back)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/export.py" line="83"/>
        <source>{0} exists and is not a folder</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="195"/>
        <source>{0} goes across a joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="193"/>
        <source>{0} goes on a joint</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="196"/>
        <source>{0} goes on a node</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="603"/>
        <source>{0} has more decimals than the box takes (at most {1} decimals){2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="264"/>
        <source>{0} has no motion profile: it holds its value, these boxes do not apply to it. Choose a shape to give it one.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="91"/>
        <source>{0} is invalid: {1} (to open {2} on it anyway, to mend it, select it in the tree first)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="576"/>
        <source>{0} is not a number{1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="602"/>
        <source>{0} is not a whole number (at most 0 decimals){1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="596"/>
        <source>{0} is outside the allowed range {1}{2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="260"/>
        <source>{0} keeps its {1} profile as stored: these boxes do not apply to it. Choose another shape to replace it.</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/exporting.py" line="71"/>
        <source>{0} module(s) not exported (Modules unchecked)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="133"/>
        <source>{0} of {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="446"/>
        <source>{0} on {1}: {2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="214"/>
        <source>{0} refused: a simulation is running; wait for it to end (its trajectory then plays) or press Cancel, then {0} again</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/base.py" line="446"/>
        <source>{0} this panel shows was deleted from the structure (press Cancel and open the panel again)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="605"/>
        <source>{0} was not taken as typed (allowed range {1}, at most {2} decimals){3}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="581"/>
        <source>{0} was not taken: the box reads only the ASCII digits 0-9, not {1}{2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="583"/>
        <source>{0} was not taken: the box reads only the digits 0-9 and {1}-{2}, not {3}{4}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="587"/>
        <source>{0} was not taken: the decimal point of this box is {1}, not {2}{3}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="593"/>
        <source>{0} was not taken: this box reads a space only between groups of three digits (a thousand is {1}){2}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/fit_target.py" line="347"/>
        <source>{0} with '{1}'; allowed: only without it (untick it to use them; ticked, it sets them itself)</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_clock.py" line="53"/>
        <source>{0} {1} ({2:+.2f})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/ranges.py" line="258"/>
        <source>{0}, row {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="181"/>
        <source>{0}, {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="247"/>
        <source>{0}: a key at {1:.3f} s lies beyond the period of {2:.3f} s: the period becomes {3:.3f} s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="78"/>
        <source>{0}: another tool's task dialog is open; finish it with OK or Cancel first</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="243"/>
        <source>{0}: keyframes play once (stored without a period) and hold the last value</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate_table.py" line="251"/>
        <source>{0}: keyframes repeat every {1:.3f} s</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/commands.py" line="86"/>
        <source>{0}: no metamaterial structure in the active document</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="85"/>
        <source>{0}: no servo angle: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="88"/>
        <source>{0}: not an actuator</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/folded_shape.py" line="112"/>
        <location filename="../../metamaterial_wb/gui/panels/new_structure.py" line="308"/>
        <location filename="../../metamaterial_wb/gui/panels/sleeve.py" line="342"/>
        <location filename="../../metamaterial_wb/gui/panels/stream.py" line="89"/>
        <source>{0}: {1}</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/animate.py" line="337"/>
        <source>{0}; centre of mass moved {1:+.2f} mm</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="211"/>
        <source>{0}; {1} is a hinge: click a node or choose one in the list (the target is still {2})</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/panels/add_module.py" line="213"/>
        <source>{0}; {1} is a node: click a hinge or choose one in the list (the target is still {2})</source>
        <translation type="unfinished"></translation>
    </message>
</context>
<context>
    <name>Workbench</name>
    <message>
        <location filename="../../metamaterial_wb/gui/workbench.py" line="22"/>
        <source>Metamaterial</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/workbench.py" line="17"/>
        <source>Metamaterial design</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/workbench.py" line="19"/>
        <source>Metamaterial fabrication</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/workbench.py" line="21"/>
        <source>Metamaterial inverse design</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/workbench.py" line="18"/>
        <source>Metamaterial simulation</source>
        <translation type="unfinished"></translation>
    </message>
    <message>
        <location filename="../../metamaterial_wb/gui/workbench.py" line="20"/>
        <source>Metamaterial sleeve</source>
        <translation type="unfinished"></translation>
    </message>
</context>
</TS>
