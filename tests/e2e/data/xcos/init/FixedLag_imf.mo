class FixedLag_imf
	parameter Real `x_11` = 0. "x_11";
	parameter Real `y_12` = 4. "y_12";
	Real `FixedLag1.x`(start=`x_11`) "";
	Real `FixedLag1.y`(start=`y_12`) "";
equation
	`FixedLag1.y` = (2. * `FixedLag1.x`);
	der(`FixedLag1.x`) = (- `FixedLag1.x`);
end FixedLag_imf;
