// A tube (od 40, wall 3, 50 tall) with a round boss (r 6, bore 3) leaving its side horizontally at
// mid-height, 12 mm out of the tube. The boss's first section lies on the tube's outer surface.
$fn = 48;
difference() {
  union() {
    cylinder(h = 50, r = 20);
    translate([0, 0, 25]) rotate([0, 90, 0]) cylinder(h = 32, r = 6);
  }
  translate([0, 0, -1]) cylinder(h = 52, r = 17);
  translate([0, 0, 25]) rotate([0, 90, 0]) cylinder(h = 33, r = 3);
}
