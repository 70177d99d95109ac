;FLAVOR:Marlin
;TIME:6
;Filament used: 0.0055m
;Layer height: 0.2
;Generated with a Cura-like writer for the lasertwin tests
M140 S60
M104 S210
M190 S60
M109 S210
M82 ;absolute extrusion mode
G28 ;Home
G92 E0
G1 F3000 Z5 ; lift
G1 F2400 E-5 ; retract
;LAYER_COUNT:2
;LAYER:0
M107
M204 S500
M205 X20 Y20
G0 F6000 X10 Y10 Z0.2
;TYPE:WALL-OUTER
G1 F2400 E0
G1 F1200 X30 Y10 E1
G1 X30 Y30 E2
G1 X10 Y30 E3
G1 X10 Y10 E4
;TYPE:SKIN
G0 F6000 X15 Y15
G1 F1200 X25 Y15 E4.5
;TIME_ELAPSED:5.5
;LAYER:1
M204 S500
G0 F6000 Z0.4
;TYPE:WALL-OUTER
G1 F1200 X25 Y25 E5
;TIME_ELAPSED:6
;End of Gcode
M107
G91 ;Relative positioning
G1 E-2 F2700 ;Retract a bit
G1 Z10 ;Raise Z
G90 ;Absolute positioning
M84
M82 ;absolute extrusion mode
