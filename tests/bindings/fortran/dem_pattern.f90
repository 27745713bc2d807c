! Another valid call pattern of the DEM library (issue 34): stop after 1000 steps instead of at
! Tfin, call ppohDEM_check_objects only every other step, and write the program's own output
! (the lowest particle) every 250 steps from particles%pos. The original's frames 1 and 2 must
! still come out byte for byte (tests/bindings/run_installed_sample.sh dem-pattern).
program dem_pattern
    use ppohDEM_util
    implicit none
    type(ppohDEM_fileinfo) :: file_info
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    type(ppohDEM_walls) :: walls
    type(ppohDEM_objects) :: objects
    type(ppohDEM_counter) :: counter
    real(kind=kreal) :: lowest, previous
    integer :: i

    call ppohDEM_loadfileinfo(file_info)
    call ppohDEM_setparameters(file_info, parameters)
    call ppohDEM_pre(file_info, parameters, particles, cells, walls, objects, counter)
    call ppohDEM_update_index(parameters, particles, cells)
    previous = huge(1.0_kreal)
    open (40, file='lowest.txt', status='replace')
    do
        call ppohDEM_check_update(parameters, particles, cells, counter)
        call ppohDEM_integrate_system(parameters, particles, cells, walls, objects)
        call ppohDEM_dataout(file_info, parameters, particles, counter)
        if (mod(counter%itime, 2) == 0) call ppohDEM_check_objects(parameters, objects, counter)
        if (mod(counter%itime, 250) == 0) then
            lowest = huge(1.0_kreal)
            do i = 1, particles%n
                lowest = min(lowest, particles%pos(i)%z)
            enddo
            write (40, '(i6,es25.17)') counter%itime, lowest
            ! The sheet falls freely for the first 5000 steps (no contacts yet).
            if (.not. lowest < previous) then
                write (0, '(a)') 'dem_pattern: particles%pos is not updated by ppohDEM_integrate_system'
                stop 1
            endif
            previous = lowest
        endif
        if (counter%itime >= 1000) exit
    enddo
    close (40)
    if (counter%file_index /= 2 .or. abs(counter%rtime - 1000 * parameters%Tstep) > 1e-9) then
        write (0, '(a)') 'dem_pattern: counter not kept by ppohDEM_dataout'
        stop 1
    endif
    call ppohDEM_exit(particles, cells, walls, objects)
end program dem_pattern
