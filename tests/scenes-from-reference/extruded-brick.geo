// A brick [0,lx] x [0,ly] x [z0,z0+lz], structured: hexahedra (tet = 0) or tetrahedra (tet = 1)
DefineConstant[ lx = 1, ly = 1, lz = 0.5, nx = 4, ny = 4, nz = 2, x0 = 0, y0 = 0, z0 = 0, tet = 0 ];
Point(1) = {x0, y0, z0};
l[] = Extrude{lx, 0, 0}{ Point{1}; Layers{nx}; };
If (tet == 0)
  s[] = Extrude{0, ly, 0}{ Line{l[1]}; Layers{ny}; Recombine; };
  v[] = Extrude{0, 0, lz}{ Surface{s[1]}; Layers{nz}; Recombine; };
Else
  s[] = Extrude{0, ly, 0}{ Line{l[1]}; Layers{ny}; };
  v[] = Extrude{0, 0, lz}{ Surface{s[1]}; Layers{nz}; };
EndIf
e = 1e-6;
Physical Volume("body") = {v[1]};
Physical Surface("bottom") = {s[1]};
Physical Surface("top") = {v[0]};
Physical Surface("ymin") = Surface In BoundingBox{x0-e, y0-e, z0-e, x0+lx+e, y0+e, z0+lz+e};
Physical Surface("xmin") = Surface In BoundingBox{x0-e, y0-e, z0-e, x0+e, y0+ly+e, z0+lz+e};
