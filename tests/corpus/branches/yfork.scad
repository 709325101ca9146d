// A column forking into two arms of unequal radius and sweep (a Y): the column's ridge in the
// skeleton's default voxels is two voxels across.
rad = 6.5;
union() {
  cylinder(h = 30, r = rad, $fn = 96);
  translate([-42, 0, 30]) rotate([90, 0, 0]) rotate_extrude(angle = 70, $fn = 200) translate([42, 0]) circle(r = rad, $fn = 96);
  translate([36, 0, 30]) rotate([90, 0, 0]) rotate([0, 0, 110]) rotate_extrude(angle = 70, $fn = 200) translate([36, 0]) circle(r = 5.5, $fn = 84);
}
