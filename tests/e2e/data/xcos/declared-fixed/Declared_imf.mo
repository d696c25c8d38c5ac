class Declared_imf
	parameter Real `initType_11` = 1. "initType_11";
	parameter Real `y_start_12` = 4. "y_start_12";
	parameter Real `initType_21` = 0. "initType_21";
	parameter Real `y_start_22` = 4. "y_start_22";
	Real `Fixed1.x`(start=0.) "";
	Real `Fixed1.y`(start=`y_start_12`) "";
	Real `Free1.x`(start=0.) "";
	Real `Free1.y`(start=`y_start_22`) "";
equation
	`Fixed1.y` = (2. * `Fixed1.x`);
	der(`Fixed1.x`) = (- `Fixed1.x`);
	`Free1.y` = (2. * `Free1.x`);
	der(`Free1.x`) = (- `Free1.x`);
end Declared_imf;
