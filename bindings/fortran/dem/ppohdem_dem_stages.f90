!! The DEM library subroutines of ppOpen-APPL/DEM 1.0 that application programs call, with the
!! original names and argument lists (external, implicit interfaces, as the original):
!!   ppohDEM_loadfileinfo     file names (./input_params_update.dat)
!!   ppohDEM_setparameters    input_params_update.dat + the original's hard-coded parameters
!!   ppohDEM_pre              random seed, the particle sheet (gfortran's random_number, as the
!!                            original), cells, walls, the object (distance_NNNN.dat,
!!                            object_mesh.stl), objects_distance.csv
!!   ppohDEM_update_index     sort the particles by cell
!!   ppohDEM_checkparameters  cell size >= particle diameter; number of output files
!!   ppohDEM_check_update     re-sort when due
!!   ppohDEM_integrate_system forces, object force, symplectic Euler
!!   ppohDEM_dataout          step counter; every Dstep steps data/outNNN.dat
!!   ppohDEM_check_objects    every Dstep steps the object's new pose, distance/objects_distanceNNN.csv
!!                            and obj/objNNN.pov
!!   ppohDEM_exit             release everything
!! The physics runs in ppohdem's C API: by default the original's arithmetic (reference/compat,
!! bit for bit); PPOHDEM_PHYSICS=corrected selects ppohdem's reference engine (docs/compat.md).
!! Environment: PPOHDEM_RANDOM_SEED=n seeds every element of random_seed with n (the original
!! uses the clock); PPOHDEM_STATE_DUMPS=0,1,500 writes fullprec/state_stepNNNNNN.dat after
!! those steps. A stage called before its prerequisite stops the program with a message.
!! docs/fortran.md.

subroutine ppohDEM_loadfileinfo(file_info)
    use ppohDEM_util
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    file_info%input_filename = './Matlab/initial.dat'
    file_info%output_filename = './data/output.dat'
    file_info%input_params_filename = './input_params_update.dat'
    file_info%ppohdem_set = 1
end subroutine

subroutine ppohDEM_setparameters(file_info, parameters)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_read_parameters, ppohdem_legacy_parameters_c
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_parameters) :: parameters
    type(ppohdem_legacy_parameters_c) :: p

    if (file_info%ppohdem_set /= 1) then
        write (0,'(a)') 'ppohDEM-Error: ppohDEM_setparameters called before ppohDEM_loadfileinfo'
        stop 1
    endif
    call ppohdem_binding_check(ppohdem_legacy_read_parameters(ppohdem_binding_cstr(file_info%input_params_filename), &
        p), 'ppohDEM_setparameters')
    parameters%Tstep = p%tstep
    parameters%Tfin = p%tfin
    parameters%Dstep = p%dstep
    parameters%Pnum = p%pnum
    parameters%L = ppohDEM_rvec3(p%length(1), p%length(2), p%length(3))
    parameters%Cn = ppohDEM_ivec3(p%cells(1), p%cells(2), p%cells(3))
    parameters%Pi = p%pi
    parameters%Radius = p%radius
    parameters%MaxRadius = 0
    parameters%Mass = p%mass
    parameters%Im = p%im
    parameters%Kn = p%kn
    parameters%Kt = p%kt
    parameters%En = p%en
    parameters%Et = p%et
    parameters%Fric_const = p%fric_const
    parameters%Gravity = p%gravity
    parameters%Size_contact_list = p%size_contact_list
    parameters%Size_contact_list_wall = p%size_contact_list_wall
    parameters%Wall_decay = 0
    parameters%Obj_n = ppohDEM_ivec3(p%obj_n(1), p%obj_n(2), p%obj_n(3))
    parameters%Obj_Kn = p%obj_kn
    parameters%Obj_En = p%obj_en
    parameters%winstart = ppohDEM_ivec3(p%winstart(1), p%winstart(2), p%winstart(3))
    parameters%vel = ppohDEM_rvec3(p%obj_velocity(1), p%obj_velocity(2), p%obj_velocity(3))
    parameters%omega = ppohDEM_rvec4(p%obj_omega(1), p%obj_omega(2), p%obj_omega(3), p%obj_omega(4))
    parameters%centroid = ppohDEM_rvec3(p%centroid(1), p%centroid(2), p%centroid(3))
    parameters%ppohdem_set = 1
end subroutine

!> ppohDEM_prepare_randomseed: every element of the seed = the clock count, or
!> PPOHDEM_RANDOM_SEED if set (the original's stored outputs used 12345).
subroutine ppohdem_binding_randomseed()
    implicit none
    integer :: seedsize, c, length, status
    integer, allocatable :: seed(:)
    character(len=32) :: text
    call system_clock(count=c)
    call get_environment_variable('PPOHDEM_RANDOM_SEED', text, length, status)
    if (status == 0 .and. length > 0) then
        read (text, *, iostat=status) c
        if (status /= 0) then
            write (0,'(a)') 'ppohDEM-Error: PPOHDEM_RANDOM_SEED: expected an integer, got "' // trim(text) // '"'
            stop 1
        endif
    endif
    call random_seed(size=seedsize)
    allocate(seed(seedsize))
    call random_seed(get=seed)
    seed = c
    call random_seed(put=seed)
end subroutine

!> ppohDEM_locate_particles_2dbox, transcribed (single-precision literals included: they decide
!> the doubles).
subroutine ppohdem_binding_locate_2dbox(parameters, particles, lx, lz, x0, z0, y0, interval_ratio)
    use ppohDEM_util
    implicit none
    integer :: i, k
    integer :: index
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    real(kind=kreal) :: lx, lz
    real(kind=kreal) :: x0, z0
    real(kind=kreal) :: y0
    real(kind=kreal) :: interval_ratio
    integer(kind=kint) :: nx, nz
    real(kind=kreal) :: interval
    real(kind=kreal), allocatable :: rn(:)

    interval=2*parameters%Radius*interval_ratio
    nx=floor(lx/interval)
    nz=floor(lz/interval)
    if(nx*nz<parameters%Pnum) then
        write (0,'(a,i0,a,i0,a)') 'ppohDEM-Error: ppohDEM_pre: the sheet holds ', nx*nz, ' particles, Pnum is ', &
            parameters%Pnum, ' (the original would leave the rest undefined)'
        stop 1
    endif
    allocate(rn(particles%n*3))
    call random_number(rn)
    do k=1,nz
        do i=1,nx
            index=i+nx*(k-1)
            if(index>parameters%Pnum) exit
            particles%pos(index)%x=x0+interval*(i-1)+parameters%Radius*interval_ratio+0.01*(rn(3*index-2)-0.5)
            particles%pos(index)%y=y0
            particles%pos(index)%z=z0+interval*(k-1)+parameters%Radius*interval_ratio+0.01*(rn(3*index)-0.5)
        enddo
    enddo
    deallocate(rn)
end subroutine

!> PPOHDEM_STATE_DUMPS: a comma-separated list of steps.
subroutine ppohdem_binding_read_dump_steps()
    use ppohDEM_util
    implicit none
    character(len=1024) :: text
    integer :: length, status, n, i, p
    if (allocated(ppohdem_binding_dump_steps)) deallocate(ppohdem_binding_dump_steps)
    call get_environment_variable('PPOHDEM_STATE_DUMPS', text, length, status)
    if (status /= 0 .or. length == 0) then
        allocate(ppohdem_binding_dump_steps(0))
        return
    endif
    n = 1
    do i = 1, length
        if (text(i:i) == ',') then
            n = n + 1
            text(i:i) = ' '
        endif
    enddo
    allocate(ppohdem_binding_dump_steps(n))
    read (text, *, iostat=p) ppohdem_binding_dump_steps
    if (p /= 0) then
        write (0,'(a)') 'ppohDEM-Error: PPOHDEM_STATE_DUMPS: expected comma-separated step numbers'
        stop 1
    endif
end subroutine

subroutine ppohdem_binding_dump_state(particles, itime)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_write_state
    implicit none
    type(ppohDEM_particles) :: particles
    integer(kind=kint) :: itime
    character(len=64) :: path
    if (.not. allocated(ppohdem_binding_dump_steps)) return
    if (.not. any(ppohdem_binding_dump_steps == itime)) return
    write (path, '("./fullprec/state_step",i6.6,".dat")') itime
    call ppohdem_binding_check(ppohdem_legacy_dem_write_state(particles%ppohdem_handle, ppohdem_binding_cstr(path)), &
        'ppohDEM_dataout (PPOHDEM_STATE_DUMPS)')
end subroutine

!> Copies positions, velocities, angular velocities and radii from ppohdem into particles.
subroutine ppohdem_binding_fetch_particles(particles, where)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_particles
    use, intrinsic :: iso_c_binding, only: c_size_t
    implicit none
    type(ppohDEM_particles) :: particles
    character(len=*) :: where
    real(kind=kreal), allocatable :: x(:), v(:), w(:)
    integer :: i
    allocate(x(3*particles%n), v(3*particles%n), w(3*particles%n))
    call ppohdem_binding_check(ppohdem_legacy_dem_particles(particles%ppohdem_handle, x, v, w, particles%radius, &
        int(particles%n, c_size_t)), where)
    do i = 1, particles%n
        particles%pos(i) = ppohDEM_rvec3(x(3*i-2), x(3*i-1), x(3*i))
        particles%vel(i) = ppohDEM_rvec3(v(3*i-2), v(3*i-1), v(3*i))
        particles%omega(i) = ppohDEM_rvec3(w(3*i-2), w(3*i-1), w(3*i))
    enddo
end subroutine

subroutine ppohdem_binding_fetch_counter(particles, counter, where)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_counter
    use, intrinsic :: iso_c_binding, only: c_int64_t, c_int32_t, c_double
    implicit none
    type(ppohDEM_particles) :: particles
    type(ppohDEM_counter) :: counter
    character(len=*) :: where
    integer(c_int64_t) :: itime
    integer(c_int32_t) :: file_index
    real(c_double) :: rtime, pos_accum
    call ppohdem_binding_check(ppohdem_legacy_dem_counter(particles%ppohdem_handle, itime, rtime, file_index, &
        pos_accum), where)
    counter%itime = int(itime, kint)
    counter%rtime = rtime
    counter%file_index = file_index
    counter%pos_accum = pos_accum
end subroutine

subroutine ppohDEM_pre(file_info, parameters, particles, cells, walls, objects, counter)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_create, ppohdem_legacy_dem_max_radius
    use, intrinsic :: iso_c_binding, only: c_size_t
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    type(ppohDEM_walls) :: walls
    type(ppohDEM_objects) :: objects
    type(ppohDEM_counter) :: counter
    real(kind=kreal), allocatable :: rn(:), positions(:)
    real(kind=kreal) :: lx, lz, x0, z0, y0, interval_ratio
    character(len=32) :: physics
    integer :: i, length, status

    if (parameters%ppohdem_set /= 1) then
        write (0,'(a)') 'ppohDEM-Error: ppohDEM_pre called before ppohDEM_setparameters'
        stop 1
    endif
    call ppohdem_binding_randomseed()

    ! ppohDEM_prepare_particles_bare
    particles%n = parameters%Pnum
    allocate(particles%radius(particles%n), particles%pos(particles%n), particles%vel(particles%n), &
             particles%force(particles%n), particles%omega(particles%n), particles%rforce(particles%n), &
             particles%cellindex(particles%n), particles%newtoorig(particles%n))
    nullify(particles%contact_list, particles%contact_list_wall)
    lx = parameters%L%x*0.9
    lz = parameters%L%z*0.9
    x0 = 0.1d0
    z0 = 5.0d0
    y0 = 0.5*parameters%L%y
    interval_ratio = 1.5d0
    call ppohdem_binding_locate_2dbox(parameters, particles, lx, lz, x0, z0, y0, interval_ratio)
    allocate(rn(particles%n*3))
    call random_number(rn)
    do i=1,particles%n
        particles%radius(i)=Parameters%Radius*(1+0.2*rn(i))
    enddo
    deallocate(rn)
    do i = 1, particles%n
        particles%vel(i) = ppohDEM_rvec3(0, 0, 0)
        particles%omega(i) = ppohDEM_rvec3(0, 0, 0)
        particles%force(i) = ppohDEM_rvec3(0, 0, 0)
        particles%rforce(i) = ppohDEM_rvec3(0, 0, 0)
        particles%newtoorig(i) = i
    enddo
    particles%cellindex = 0

    ! The physics, from here on in ppohdem.
    physics = 'ppohdem-1.0'
    call get_environment_variable('PPOHDEM_PHYSICS', physics, length, status)
    if (status /= 0 .or. length == 0) physics = 'ppohdem-1.0'
    allocate(positions(3*particles%n))
    do i = 1, particles%n
        positions(3*i-2) = particles%pos(i)%x
        positions(3*i-1) = particles%pos(i)%y
        positions(3*i) = particles%pos(i)%z
    enddo
    call ppohdem_binding_check(ppohdem_legacy_dem_create(ppohdem_binding_cstr(file_info%input_params_filename), &
        ppohdem_binding_cstr('.'), ppohdem_binding_cstr(physics), int(particles%n, c_size_t), positions, &
        particles%radius, particles%ppohdem_handle), 'ppohDEM_pre')
    objects%ppohdem_handle = particles%ppohdem_handle

    ! ppohDEM_prepare_cells, ppohDEM_prepare_walls (the fields programs may read)
    cells%cellsize = ppohDEM_rvec3(parameters%L%x/parameters%Cn%x, parameters%L%y/parameters%Cn%y, &
                                   parameters%L%z/parameters%Cn%z)
    cells%cellnum = parameters%Cn
    cells%n = parameters%Cn%x*parameters%Cn%y*parameters%Cn%z
    nullify(cells%nei_cellindex, cells%start_partindex, cells%end_partindex)
    walls%n = 6
    allocate(walls%point(6), walls%nvec(6))
    walls%point(1:3) = ppohDEM_rvec3(0, 0, 0)
    walls%point(4:6) = parameters%L
    walls%nvec(1) = ppohDEM_rvec3(1, 0, 0)
    walls%nvec(2) = ppohDEM_rvec3(0, 1, 0)
    walls%nvec(3) = ppohDEM_rvec3(0, 0, 1)
    walls%nvec(4) = ppohDEM_rvec3(-1, 0, 0)
    walls%nvec(5) = ppohDEM_rvec3(0, -1, 0)
    walls%nvec(6) = ppohDEM_rvec3(0, 0, -1)
    ! ppohDEM_prepare_objects_fromfile (the field itself stays in ppohdem)
    objects%gridnum = parameters%Obj_n
    objects%gridsize = ppohDEM_rvec3(parameters%L%x/(objects%gridnum%x-1), parameters%L%y/(objects%gridnum%y-1), &
                                     parameters%L%z/(objects%gridnum%z-1))
    objects%gn = objects%gridnum%x*objects%gridnum%y*objects%gridnum%z
    objects%winstart = parameters%winstart
    objects%vel = parameters%vel
    objects%omega = ppohDEM_rvec4(parameters%omega%x, parameters%omega%y, parameters%omega%z, &
                                  - parameters%Pi / parameters%omega%w)
    objects%centroid = parameters%centroid
    nullify(objects%distance, objects%scaled_distance, objects%read_distance_3D, objects%winpos_3D, objects%move_3D, &
            objects%mesh_v1, objects%mesh_v2, objects%mesh_v3)
    objects%n_mesh = 0

    counter%itime = 0
    counter%rtime = 0.
    counter%file_index = 0
    counter%pos_accum = 0.
    call ppohdem_binding_check(ppohdem_legacy_dem_max_radius(particles%ppohdem_handle, parameters%MaxRadius), &
        'ppohDEM_pre')
    write (*,"(1A,1F10.6)") 'objects%vel%x: ', objects%vel%x
    call ppohdem_binding_read_dump_steps()
    call ppohdem_binding_dump_state(particles, counter%itime)
end subroutine

subroutine ppohDEM_update_index(parameters, particles, cells)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_update_index
    implicit none
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    call ppohdem_binding_require(particles%ppohdem_handle, 'ppohDEM_update_index', 'ppohDEM_pre')
    call ppohdem_binding_check(ppohdem_legacy_dem_update_index(particles%ppohdem_handle), 'ppohDEM_update_index')
    call ppohdem_binding_fetch_particles(particles, 'ppohDEM_update_index')
end subroutine

subroutine ppohDEM_checkparameters(parameters, particles, cells)
    use ppohDEM_util
    implicit none
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    call ppohdem_binding_require(particles%ppohdem_handle, 'ppohDEM_checkparameters', 'ppohDEM_pre')
    if(cells%cellsize%x-2*parameters%MaxRadius<0.)then
        write(*,*) ' ppohDEM-Error: cell size is smaller than a particle diameter'
        stop
    endif
    parameters%Dfin=ceiling(parameters%Tfin/(parameters%Tstep*parameters%Dstep))
    write(*,'(" Note: ppohDEM will output ",i3.3," data files")') parameters%Dfin
end subroutine

subroutine ppohDEM_check_update(parameters, particles, cells, counter)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_check_update
    use, intrinsic :: iso_c_binding, only: c_int32_t
    implicit none
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    type(ppohDEM_counter) :: counter
    integer(c_int32_t) :: resorted
    call ppohdem_binding_require(particles%ppohdem_handle, 'ppohDEM_check_update', 'ppohDEM_pre')
    call ppohdem_binding_check(ppohdem_legacy_dem_check_update(particles%ppohdem_handle, resorted), &
        'ppohDEM_check_update')
    call ppohdem_binding_fetch_counter(particles, counter, 'ppohDEM_check_update')
end subroutine

subroutine ppohDEM_integrate_system(parameters, particles, cells, walls, objects)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_integrate
    implicit none
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    type(ppohDEM_walls) :: walls
    type(ppohDEM_objects) :: objects
    call ppohdem_binding_require(particles%ppohdem_handle, 'ppohDEM_integrate_system', 'ppohDEM_pre')
    call ppohdem_binding_check(ppohdem_legacy_dem_integrate(particles%ppohdem_handle), 'ppohDEM_integrate_system')
    call ppohdem_binding_fetch_particles(particles, 'ppohDEM_integrate_system')
end subroutine

subroutine ppohDEM_dataout(file_info, parameters, particles, counter)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_dataout
    use, intrinsic :: iso_c_binding, only: c_int32_t
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_counter) :: counter
    integer(c_int32_t) :: frame
    call ppohdem_binding_require(particles%ppohdem_handle, 'ppohDEM_dataout', 'ppohDEM_pre')
    call ppohdem_binding_check(ppohdem_legacy_dem_dataout(particles%ppohdem_handle, frame), 'ppohDEM_dataout')
    call ppohdem_binding_fetch_counter(particles, counter, 'ppohDEM_dataout')
    if (frame == 1) then
        write (*,'(" *** outputting   file:",i3.3)') counter%file_index
        write (file_info%output_filename,'("./data/out",i3.3,".dat")') counter%file_index
    endif
    call ppohdem_binding_dump_state(particles, counter%itime)
end subroutine

subroutine ppohDEM_check_objects(parameters, objects, counter)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_check_objects
    use, intrinsic :: iso_c_binding, only: c_int32_t
    implicit none
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_objects) :: objects
    type(ppohDEM_counter) :: counter
    integer(c_int32_t) :: updated
    call ppohdem_binding_require(objects%ppohdem_handle, 'ppohDEM_check_objects', 'ppohDEM_pre')
    call ppohdem_binding_check(ppohdem_legacy_dem_check_objects(objects%ppohdem_handle, updated), &
        'ppohDEM_check_objects')
end subroutine

subroutine ppohDEM_exit(particles, cells, walls, objects)
    use ppohDEM_util
    use ppohdem_c_interface, only: ppohdem_legacy_dem_destroy
    use, intrinsic :: iso_c_binding, only: c_null_ptr
    implicit none
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    type(ppohDEM_walls) :: walls
    type(ppohDEM_objects) :: objects
    integer :: status
    call ppohdem_binding_require(particles%ppohdem_handle, 'ppohDEM_exit', 'ppohDEM_pre')
    status = ppohdem_legacy_dem_destroy(particles%ppohdem_handle)
    particles%ppohdem_handle = c_null_ptr
    objects%ppohdem_handle = c_null_ptr
    deallocate(particles%radius, particles%pos, particles%vel, particles%force, particles%omega, particles%rforce, &
               particles%cellindex, particles%newtoorig)
    deallocate(walls%point, walls%nvec)
end subroutine
