// A candelabra: a column on a foot, two arms leaving its side horizontally at different heights
// and azimuths, each turning up through 90 degrees into a short vertical candle holder.
$fn = 40;
module arm(z, az, reach, bend) {
  rotate([0, 0, az]) translate([0, 0, z]) {
    rotate([0, 90, 0]) cylinder(h = reach, r = 4);                       // horizontal out of the column
    translate([reach, 0, bend]) rotate([90, 0, 0]) rotate([0, 0, 270]) rotate_extrude(angle = 90, $fn = 60) translate([bend, 0]) circle(r = 4);
    translate([reach + bend, 0, bend]) cylinder(h = 14, r = 4);           // vertical holder
    translate([reach + bend, 0, bend + 14]) cylinder(h = 4, r = 7);       // drip cup
  }
}
union() {
  cylinder(h = 4, r = 16);
  cylinder(h = 70, r = 6);
  arm(20, 0, 18, 10);
  arm(38, 180, 14, 8);
  translate([0, 0, 70]) cylinder(h = 4, r = 8);
}
