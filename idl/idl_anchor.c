/* The generated type support (fleet.c) is compiled into this library through fleet_idl_generated. */
