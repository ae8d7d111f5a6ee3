// POV-Ray 3.7 port of examples/cornell.wsd (the report's Figure 1) for the speed comparison in
// bench/cornell_vs_povray.sh: same geometry, camera, 10x10 jittered area light, depth 5 (POV-Ray's
// max_trace_level counts the camera ray, so 6). Image textures are replaced by plain pigments:
// only ray counts and CPU time are compared, not pixels.
#version 3.7;
global_settings { max_trace_level 6 ambient_light 1 assumed_gamma 1.0 }
camera { perspective location <0, 0, -550> look_at <0, 0, 500> up y right x angle 60 }
light_source { <25, 500, 625> color rgb 1
  area_light <50, 0, 0>, <0, 0, 50>, 10, 10 jitter
#ifdef (ADAPTIVE) adaptive 1 #end
}
#declare Flat = finish { ambient 0.2 diffuse 1 specular 0 }
#macro Wall(C, U, V, Col)
  mesh { triangle { C, C + U, C + U + V } triangle { C, C + U + V, C + V }
         texture { pigment { color rgb Col } finish { Flat } } }
#end
Wall(<-600, -600, 0>, <1200, 0, 0>, <0, 0, 1200>, <0.5, 0.5, 0.5>)
Wall(<-600, -600, 0>, <0, 0, 1200>, <0, 1200, 0>, <1, 0, 0>)
Wall(<600, -600, 1200>, <0, 0, -1200>, <0, 1200, 0>, <0, 1, 0>)
Wall(<-600, -600, 1200>, <1200, 0, 0>, <0, 1200, 0>, <90, 111, 219> / 255)
Wall(<-600, 600, 1200>, <1200, 0, 0>, <0, 0, -1200>, <1, 1, 1>)
sphere { <200, 0, 880>, 200 texture { pigment { color rgb <0.1, 0.3, 0.6> }
         finish { ambient 0.2 diffuse 1 phong 0.5 phong_size 500 reflection 0.1 } } }
sphere { <-300, 200, 800>, 100 texture { pigment { color rgb 0.5 } finish { Flat } } }
sphere { <-80, -180, 130>, 70 texture { pigment { color rgbf <1, 1, 1, 1> }
         finish { ambient 0 diffuse 0 phong 0.5 phong_size 500 reflection { 0, 1 fresnel on } conserve_energy } }
         interior { ior 1.5 } }
sphere { <500, -500, 550>, 100 texture { pigment { color rgb <116, 0, 158> / 255 }
         finish { ambient 0.2 diffuse 1 phong 0.5 phong_size 500 reflection 0.01 } } }
sphere { <350, -550, 550>, 50 texture { pigment { color rgb <237, 162, 33> / 255 } finish { Flat } } }
sphere { <-350, -500, 600>, 100 texture { pigment { bozo turbulence 1 scale 50
         color_map { [0 color rgb <0.05, 0.3, 0.5>] [1 color rgb <0.45, 0.78, 0.3>] } } finish { Flat } } }
box { <-125, -125, -125>, <125, 125, 125> rotate <0, 0, 45> rotate <35.264, 0, 0> translate <-400, -350, 990>
      texture { pigment { color rgb <0.9, 0.9, 0.9> } finish { Flat } } }
