!! ppohdem_c_interface: ISO_C_BINDING interfaces to the C API (bindings/c/include/ppohdem/ppohdem.h)
!! used by the two ppohDEM_util modules (DEM-Util and DEM). Interfaces only: no procedures, so
!! both libraries can compile it. docs/fortran.md "How the modules work".
module ppohdem_c_interface
    use, intrinsic :: iso_c_binding
    implicit none
    public

    integer(c_int), parameter :: PPOHDEM_OK = 0

    type, bind(c) :: ppohdem_legacy_parameters_c
        real(c_double) :: tstep, tfin
        integer(c_int32_t) :: dstep, pnum
        real(c_double) :: length(3)
        integer(c_int32_t) :: cells(3)
        real(c_double) :: pi, radius, mass, im, kn, kt, en, et, fric_const, gravity, obj_kn, obj_en
        integer(c_int32_t) :: size_contact_list, size_contact_list_wall
        integer(c_int32_t) :: obj_n(3), winstart(3)
        real(c_double) :: obj_velocity(3), obj_omega(4), centroid(3)
    end type

    interface
        function ppohdem_last_error() bind(c, name='ppohdem_last_error')
            import :: c_ptr
            type(c_ptr) :: ppohdem_last_error
        end function

        ! ---- DEM-Util stages
        integer(c_int) function ppohdem_util_create(input_file, nprocs, rank, util) bind(c, name='ppohdem_util_create')
            import :: c_int, c_char, c_int32_t, c_ptr
            character(kind=c_char), intent(in) :: input_file(*)
            integer(c_int32_t), value :: nprocs, rank
            type(c_ptr), intent(out) :: util
        end function
        integer(c_int) function ppohdem_util_destroy(util) bind(c, name='ppohdem_util_destroy')
            import :: c_int, c_ptr
            type(c_ptr), value :: util
        end function
        integer(c_int) function ppohdem_util_read_mesh(util) bind(c, name='ppohdem_util_read_mesh')
            import :: c_int, c_ptr
            type(c_ptr), value :: util
        end function
        integer(c_int) function ppohdem_util_facet_count(util, count) bind(c, name='ppohdem_util_facet_count')
            import :: c_int, c_ptr, c_size_t
            type(c_ptr), value :: util
            integer(c_size_t), intent(out) :: count
        end function
        integer(c_int) function ppohdem_util_voxelize(util, out_prefix) bind(c, name='ppohdem_util_voxelize')
            import :: c_int, c_ptr, c_char
            type(c_ptr), value :: util
            character(kind=c_char), intent(in) :: out_prefix(*)
        end function
        integer(c_int) function ppohdem_util_pass1(util) bind(c, name='ppohdem_util_pass1')
            import :: c_int, c_ptr
            type(c_ptr), value :: util
        end function
        integer(c_int) function ppohdem_util_exact_band(util) bind(c, name='ppohdem_util_exact_band')
            import :: c_int, c_ptr
            type(c_ptr), value :: util
        end function
        integer(c_int) function ppohdem_util_pass2(util) bind(c, name='ppohdem_util_pass2')
            import :: c_int, c_ptr
            type(c_ptr), value :: util
        end function
        integer(c_int) function ppohdem_util_write(util, out_prefix) bind(c, name='ppohdem_util_write')
            import :: c_int, c_ptr, c_char
            type(c_ptr), value :: util
            character(kind=c_char), intent(in) :: out_prefix(*)
        end function
        integer(c_int) function ppohdem_util_field(util, distance, inside, count) bind(c, name='ppohdem_util_field')
            import :: c_int, c_ptr, c_double, c_int32_t, c_size_t
            type(c_ptr), value :: util
            real(c_double), intent(out) :: distance(*)
            integer(c_int32_t), intent(out) :: inside(*)
            integer(c_size_t), value :: count
        end function

        ! ---- DEM stages
        integer(c_int) function ppohdem_legacy_read_parameters(params_file, parameters) &
                bind(c, name='ppohdem_legacy_read_parameters')
            import :: c_int, c_char, ppohdem_legacy_parameters_c
            character(kind=c_char), intent(in) :: params_file(*)
            type(ppohdem_legacy_parameters_c), intent(out) :: parameters
        end function
        integer(c_int) function ppohdem_legacy_dem_create(params_file, work_dir, physics, count, positions, radius, dem) &
                bind(c, name='ppohdem_legacy_dem_create')
            import :: c_int, c_char, c_size_t, c_double, c_ptr
            character(kind=c_char), intent(in) :: params_file(*), work_dir(*), physics(*)
            integer(c_size_t), value :: count
            real(c_double), intent(in) :: positions(*), radius(*)
            type(c_ptr), intent(out) :: dem
        end function
        integer(c_int) function ppohdem_legacy_dem_destroy(dem) bind(c, name='ppohdem_legacy_dem_destroy')
            import :: c_int, c_ptr
            type(c_ptr), value :: dem
        end function
        integer(c_int) function ppohdem_legacy_dem_update_index(dem) bind(c, name='ppohdem_legacy_dem_update_index')
            import :: c_int, c_ptr
            type(c_ptr), value :: dem
        end function
        integer(c_int) function ppohdem_legacy_dem_check_update(dem, done) bind(c, name='ppohdem_legacy_dem_check_update')
            import :: c_int, c_ptr, c_int32_t
            type(c_ptr), value :: dem
            integer(c_int32_t), intent(out) :: done
        end function
        integer(c_int) function ppohdem_legacy_dem_integrate(dem) bind(c, name='ppohdem_legacy_dem_integrate')
            import :: c_int, c_ptr
            type(c_ptr), value :: dem
        end function
        integer(c_int) function ppohdem_legacy_dem_dataout(dem, done) bind(c, name='ppohdem_legacy_dem_dataout')
            import :: c_int, c_ptr, c_int32_t
            type(c_ptr), value :: dem
            integer(c_int32_t), intent(out) :: done
        end function
        integer(c_int) function ppohdem_legacy_dem_check_objects(dem, done) bind(c, name='ppohdem_legacy_dem_check_objects')
            import :: c_int, c_ptr, c_int32_t
            type(c_ptr), value :: dem
            integer(c_int32_t), intent(out) :: done
        end function
        integer(c_int) function ppohdem_legacy_dem_counter(dem, itime, rtime, file_index, pos_accum) &
                bind(c, name='ppohdem_legacy_dem_counter')
            import :: c_int, c_ptr, c_int64_t, c_double, c_int32_t
            type(c_ptr), value :: dem
            integer(c_int64_t), intent(out) :: itime
            real(c_double), intent(out) :: rtime, pos_accum
            integer(c_int32_t), intent(out) :: file_index
        end function
        integer(c_int) function ppohdem_legacy_dem_max_radius(dem, max_radius) bind(c, name='ppohdem_legacy_dem_max_radius')
            import :: c_int, c_ptr, c_double
            type(c_ptr), value :: dem
            real(c_double), intent(out) :: max_radius
        end function
        integer(c_int) function ppohdem_legacy_dem_particles(dem, positions, velocities, angular_velocities, radius, count) &
                bind(c, name='ppohdem_legacy_dem_particles')
            import :: c_int, c_ptr, c_double, c_size_t
            type(c_ptr), value :: dem
            real(c_double), intent(out) :: positions(*), velocities(*), angular_velocities(*), radius(*)
            integer(c_size_t), value :: count
        end function
        integer(c_int) function ppohdem_legacy_dem_write_state(dem, path) bind(c, name='ppohdem_legacy_dem_write_state')
            import :: c_int, c_ptr, c_char
            type(c_ptr), value :: dem
            character(kind=c_char), intent(in) :: path(*)
        end function
    end interface
end module ppohdem_c_interface
