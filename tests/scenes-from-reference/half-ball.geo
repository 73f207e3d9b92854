// The lower half of a ball (radius R, centre (0, 0, R)): its flat top at z = R, its pole at the origin. Tetrahedra of
// size h (divided by refine).
SetFactory("OpenCASCADE");
DefineConstant[R = 1, h = 0.2, refine = 1];
Sphere(1) = {0, 0, R, R};
Box(2) = {-2 * R, -2 * R, R, 4 * R, 4 * R, 2 * R};
BooleanDifference(3) = {Volume{1}; Delete;}{Volume{2}; Delete;};
Mesh.CharacteristicLengthMax = h / refine;
Mesh.CharacteristicLengthMin = h / refine;
eps = 1e-6 * R;
top[] = Surface In BoundingBox{-2 * R, -2 * R, R - eps, 2 * R, 2 * R, R + eps};
all[] = Boundary{Volume{3};};
curved[] = all[];
curved[] -= top[];
Physical Volume("ball") = {3};
Physical Surface("top") = {top[]};
Physical Surface("surface") = {curved[]};
