// POV-Ray 3.7 port of examples/cornell-caustics.wsd for bench/caustics_vs_povray.sh: the same box,
// camera, 6x6 jittered area light, glass and mirror spheres, with POV-Ray's photon map for the
// caustics (`count` from the command line: Declare=PHOTONS=N). wsd's depth 8 is POV-Ray's
// max_trace_level 9 (it counts the camera ray). Both have lights without distance falloff.
#version 3.7;
#ifndef (PHOTONS) #declare PHOTONS = 400000; #end
global_settings { max_trace_level 9 ambient_light 1 assumed_gamma 1.0
  photons { count PHOTONS  max_trace_level 9  autostop 0 } }
camera { perspective location <0, 300, -500> look_at <-50, -350, 600> up y right x angle 60 }
light_source { <0, 590, 1000> color rgb 0.9
  area_light <150, 0, 0>, <0, 0, 150>, 6, 6 jitter
  photons { refraction on reflection on } }
#declare Flat = finish { ambient 0.1 diffuse 1 specular 0 }
#macro Wall(C, U, V, Col)
  mesh { triangle { C, C + U, C + U + V } triangle { C, C + U + V, C + V }
         texture { pigment { color rgb Col } finish { Flat } } }
#end
Wall(<-600, -600, 0>, <1200, 0, 0>, <0, 0, 1200>, <0.8, 0.8, 0.8>)
Wall(<-600, -600, 0>, <0, 0, 1200>, <0, 1200, 0>, <0.75, 0.1, 0.1>)
Wall(<600, -600, 1200>, <0, 0, -1200>, <0, 1200, 0>, <0.1, 0.65, 0.15>)
Wall(<-600, -600, 1200>, <1200, 0, 0>, <0, 1200, 0>, <0.8, 0.8, 0.8>)
Wall(<-600, 600, 1200>, <1200, 0, 0>, <0, 0, -1200>, <0.8, 0.8, 0.8>)
sphere { <-150, -360, 600>, 160 texture { pigment { color rgbf <1, 1, 1, 1> }
         finish { ambient 0 diffuse 0 phong 0.6 phong_size 800 reflection { 0, 1 fresnel on } conserve_energy } }
         interior { ior 1.5 }
         photons { target refraction on reflection on collect off } }
cylinder { <-470, -600, 860>, <-470, -250, 860>, 40 texture { pigment { color rgb 0.8 } finish { Flat } } }
sphere { <300, -420, 800>, 180 texture { pigment { color rgb 1 }
         finish { ambient 0.1 diffuse 0 phong 0.5 phong_size 500 reflection 0.9 } }
         photons { target reflection on collect off } }
