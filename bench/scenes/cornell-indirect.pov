// POV-Ray 3.7 port of examples/cornell-indirect.wsd for bench/indirect_vs_povray.sh: the same
// walls, block, sphere, 4x4 jittered area light (no falloff, as wsd's lights) and glowing panel,
// with radiosity in place of wsd's indirect light (ambient 0; the panel an `emission` finish).
// COUNT (radiosity rays a sample) and BOUNCES (recursion_limit) are declared on the command line.
#version 3.7;
#ifndef (COUNT) #declare COUNT = 50; #end
#ifndef (BOUNCES) #declare BOUNCES = 3; #end
global_settings {
  max_trace_level 6 assumed_gamma 1.0 ambient_light 0
  radiosity { count COUNT recursion_limit BOUNCES error_bound 0.5 nearest_count 10
              pretrace_start 0.08 pretrace_end 0.01 low_error_factor 0.5 brightness 1 always_sample off }
}
camera { perspective location <0, 0, -3.4> look_at <0, 0, 0> up y right x angle 40 }
light_source { <0, 0.98, 0> color rgb 1 area_light <0.5, 0, 0>, <0, 0, 0.5>, 4, 4 jitter }
#declare Flat = finish { ambient 0 diffuse 1 specular 0 }
#macro Wall(C, U, V, Col)
  mesh { triangle { C, C + U, C + U + V } triangle { C, C + U + V, C + V }
         texture { pigment { color rgb Col } finish { Flat } } }
#end
Wall(<-1, -1, -1>, <2, 0, 0>, <0, 0, 2>, 0.75)
Wall(<-1, 1, -1>, <0, 0, 2>, <2, 0, 0>, 0.75)
Wall(<-1, -1, 1>, <2, 0, 0>, <0, 2, 0>, 0.75)
Wall(<-1, -1, -1>, <0, 2, 0>, <0, 0, 2>, <0.75, 0.12, 0.1>)
Wall(<1, -1, -1>, <0, 0, 2>, <0, 2, 0>, <0.12, 0.75, 0.1>)
box { <-0.25, 0.985, -0.25>, <0.25, 0.995, 0.25>
      texture { pigment { color rgb 1 } finish { ambient 0 diffuse 0 emission 1 } } }
box { <-0.3, -1, -0.3>, <0.3, 0.2, 0.3> translate <-0.35, 0, 0.4>
      texture { pigment { color rgb 0.75 } finish { Flat } } }
sphere { <0.45, -0.6, -0.2>, 0.4 texture { pigment { color rgb 0.75 } finish { Flat } } }
